//! What the render commands print while they work: the samples asked for, the progress bar
//! and the time budget's report (shared by the CPU and GPU paths of `render`).

use indicatif::{ProgressBar, ProgressStyle};
use std::time::Duration;

/// The samples asked for, as the render commands log them: "64 spp", or "spp until 2s" for a
/// time budget alone.
pub(crate) fn spp_text(spp: Option<u32>, budget: Option<Duration>) -> String {
    match (spp, budget) {
        (Some(n), _) => format!("{n} spp"),
        (None, Some(b)) => format!("spp until {b:?}"),
        (None, None) => "spp unbounded".to_owned(),
    }
}

/// With a time budget, one line on how far it got: the spp reached and the pass size (the
/// most the last pass can overrun the budget by).
pub(crate) fn budget_report(budget: Option<Duration>, spp: u64, pass_spp: u32) {
    if let Some(b) = budget {
        eprintln!("time budget {b:?}: {spp} spp reached in passes of {pass_spp} spp");
    }
}

/// The render commands' progress bar over `spp` samples per pixel, a counter of samples
/// when only a time budget bounds them (hidden when `quiet`).
pub(crate) fn spp_progress_bar(spp: Option<u32>, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let (bar, template) = match spp {
        Some(n) => (
            ProgressBar::new(n as u64),
            "{bar:40} {pos}/{len} spp  {elapsed_precise} eta {eta}",
        ),
        None => (
            ProgressBar::new_spinner(),
            "{spinner} {pos} spp  {elapsed_precise}",
        ),
    };
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar
}
