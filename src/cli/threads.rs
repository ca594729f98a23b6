//! The worker threads of the CPU renderer (`--threads`).

use anyhow::Result;

/// A rayon pool of `threads` workers (default: all cores); a failure is one line naming the
/// flag and the OS's reason once.
pub(super) fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    // Far more than any machine's cores; more would only exhaust the OS (or take minutes).
    const MAX_THREADS: usize = 4096;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(t) = threads {
        anyhow::ensure!(
            t <= MAX_THREADS,
            "--threads {t} is more than {MAX_THREADS} worker threads"
        );
        pool = pool.num_threads(t);
    }
    pool.build().map_err(|e| match threads {
        Some(t) => anyhow::anyhow!("--threads {t}: cannot start {t} worker threads ({e})"),
        None => anyhow::anyhow!("cannot start worker threads ({e})"),
    })
}
