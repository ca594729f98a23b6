//! Command-line conventions (issue 37 item 6): `--version` names the git revision, and the
//! shell completions and the manual page are generated from the same definition as `--help`.

use std::process::Command;

/// `refract ARGS`: its standard output; it must succeed.
fn stdout(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_refract"))
        .args(args)
        .output()
        .expect("run refract");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn version_names_the_git_revision() {
    let v = stdout(&["--version"]);
    assert!(v.starts_with("refract 0."), "{v}");
    assert!(v.contains("(git "), "{v}");
}

#[test]
fn completions_and_the_manual_cover_every_subcommand() {
    let bash = stdout(&["completions", "bash"]);
    let man = stdout(&["man"]);
    assert!(man.contains(".TH refract 1"), "a roff manual page");
    for sub in ["view", "render", "trace", "bench", "merge"] {
        assert!(bash.contains(sub), "bash completion lacks '{sub}'");
        assert!(man.contains(sub), "the manual lacks '{sub}'");
    }
    let zsh = stdout(&["completions", "zsh"]);
    assert!(zsh.contains("#compdef refract"), "a zsh completion");
    assert!(
        !bash.contains("__probe-window") || !man.contains("__probe-window"),
        "hidden"
    );
}
