//! A presentation clicker: remotes send PageDown/PageUp (or the arrow keys), so those step
//! through the demos in lecture order; Home and End go to the first and the last. Keys are
//! left alone while a widget (a text field, a focused slider) has the keyboard.

use super::DEMOS;
use crate::app::ViewerApp;
use eframe::egui;

/// One press of the clicker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    Next,
    Previous,
    First,
    Last,
}

/// The demo a press leads to from `current` (None: no demo open) among `n`. Next from the
/// last and Previous from the first stay (a clicker does not wrap round mid-lecture).
pub fn target(current: Option<usize>, step: Step, n: usize) -> Option<usize> {
    let last = n.checked_sub(1)?;
    Some(match (step, current) {
        (Step::First, _) | (Step::Next, None) => 0,
        (Step::Last, _) | (Step::Previous, None) => last,
        (Step::Next, Some(k)) => (k + 1).min(last),
        (Step::Previous, Some(k)) => k.saturating_sub(1),
    })
}

/// The clicker press in this frame's input, consumed.
fn step_pressed(ctx: &egui::Context) -> Option<Step> {
    use egui::{Key, Modifiers};
    ctx.input_mut(|i| {
        let mut any = |keys: &[Key]| {
            // Consume every listed key (no short-circuit: one press, one step).
            let mut hit = false;
            for &k in keys {
                hit |= i.consume_key(Modifiers::NONE, k);
            }
            hit
        };
        if any(&[Key::PageDown, Key::ArrowRight, Key::ArrowDown]) {
            Some(Step::Next)
        } else if any(&[Key::PageUp, Key::ArrowLeft, Key::ArrowUp]) {
            Some(Step::Previous)
        } else if any(&[Key::Home]) {
            Some(Step::First)
        } else if any(&[Key::End]) {
            Some(Step::Last)
        } else {
            None
        }
    })
}

impl ViewerApp {
    /// The open demo's place in the lecture: (k, n), k counted from 1.
    pub fn lecture_position(&self) -> Option<(usize, usize)> {
        self.lecture_caption()?;
        Some((self.lecture.active? + 1, DEMOS.len()))
    }

    /// Step through the demos with the clicker's keys.
    pub(in crate::app) fn handle_clicker(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let Some(step) = step_pressed(ctx) else {
            return;
        };
        let current = self.lecture_position().map(|(k, _)| k - 1);
        if let Some(t) = target(current, step, DEMOS.len())
            && Some(t) != current
        {
            self.start_demo(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clicker_walks_forward_and_back_without_wrapping() {
        let n = 5;
        assert_eq!(target(None, Step::Next, n), Some(0));
        assert_eq!(target(None, Step::Previous, n), Some(4));
        assert_eq!(target(Some(2), Step::Next, n), Some(3));
        assert_eq!(target(Some(4), Step::Next, n), Some(4));
        assert_eq!(target(Some(0), Step::Previous, n), Some(0));
        assert_eq!(target(Some(3), Step::First, n), Some(0));
        assert_eq!(target(Some(1), Step::Last, n), Some(4));
        assert_eq!(target(None, Step::Next, 0), None);
    }
}
