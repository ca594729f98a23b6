//! `refract` command line: view | render | trace | bench | merge | lecture. No subcommand opens the viewer.

use clap::Parser;

mod cli;

fn main() {
    // Vulkan drivers complain on stderr when XDG_RUNTIME_DIR is unset (headless machines, CI).
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        let dir = std::env::temp_dir().join(format!("refract-xdg-{}", std::process::id()));
        if std::fs::create_dir_all(&dir).is_ok() {
            // SAFETY: called first thing in `main`, before any other thread exists, so no
            // concurrent reader of the environment can observe the write.
            unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        }
    }
    if let Err(e) = cli::run(cli::Cli::parse()) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
