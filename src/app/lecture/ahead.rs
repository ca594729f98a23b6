//! Preparing the demos a lecture is likely to open next: when a demo opens, a helper thread
//! loads the scenes of the demos before and after it (the clicker's two directions) with the
//! render options the viewer would give them, and the backend prepares for each
//! (`Backend::prepare_for`: the GPU compiles the general kernel of its family ahead of need),
//! so that stepping to the next demo shows an image at once instead of a frozen one while
//! its kernels compile. The UI thread never waits: it collects what is ready each frame.

use super::DEMOS;
use crate::render::RenderOptions;
use crate::render::settings::ViewerSettings;
use crate::scene::Scene;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Arc, Mutex};

/// A neighbouring demo's scene and the options the viewer would render it with.
type Prepared = (Scene, RenderOptions);

/// Scenes and options of neighbouring demos, arriving from the helper thread.
#[derive(Clone, Debug, Default)]
pub struct Ahead {
    incoming: Option<Arc<Mutex<Receiver<Prepared>>>>,
    /// How many neighbours were handed to the backend (tests and the status line).
    pub prepared: u32,
}

/// The demos a clicker reaches next from `index`: the following one, then the previous.
pub fn neighbours(index: usize) -> Vec<usize> {
    let mut n = Vec::new();
    if index + 1 < DEMOS.len() {
        n.push(index + 1);
    }
    if let Some(p) = index.checked_sub(1) {
        n.push(p);
    }
    n
}

impl Ahead {
    /// Start loading the neighbours of demo `index` with `settings` (the viewer's, the
    /// demo's path filter applied to each); what was still arriving for another demo is
    /// dropped.
    pub fn start(&mut self, index: usize, settings: &ViewerSettings) {
        let (tx, rx) = channel();
        let settings = settings.clone();
        let spawned = std::thread::Builder::new()
            .name("refract-lecture-ahead".into())
            .spawn(move || {
                for k in neighbours(index) {
                    let demo = &DEMOS[k];
                    let Ok(scene) = Scene::load(demo.scene) else {
                        continue;
                    };
                    let mut s = settings.clone();
                    s.render.paths = demo.filter.to_owned();
                    let Ok(opts) = s.render_options(&scene) else {
                        continue;
                    };
                    if tx.send((scene, opts)).is_err() {
                        return;
                    }
                }
            });
        // Without a thread there is nothing to prepare; the demos still open as before.
        self.incoming = spawned.ok().map(|_| Arc::new(Mutex::new(rx)));
    }

    /// What has arrived since the last call (never waits).
    pub fn take_ready(&mut self) -> Vec<Prepared> {
        let Some(rx) = &self.incoming else {
            return Vec::new();
        };
        let mut out = Vec::new();
        let mut finished = false;
        if let Ok(rx) = rx.lock() {
            loop {
                match rx.try_recv() {
                    Ok(x) => out.push(x),
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => {
                        finished = true;
                        break;
                    }
                }
            }
        }
        if finished {
            self.incoming = None;
        }
        self.prepared += out.len() as u32;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_neighbours_are_the_next_then_the_previous_demo() {
        assert_eq!(neighbours(0), vec![1]);
        assert_eq!(neighbours(3), vec![4, 2]);
        assert_eq!(neighbours(DEMOS.len() - 1), vec![DEMOS.len() - 2]);
    }
}
