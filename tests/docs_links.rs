//! The README and the book under `docs/` stay whole: every relative link and image target
//! exists next to the file that names it and is tracked by git (a file left out of a commit
//! would be a broken picture on the repository's front page), the README stays a front page
//! (at most 250 lines), and it keeps the line CI runs as "the README's test command".
//!
//! Plain std: the Markdown is scanned for inline links and images `[text](target)` /
//! `![alt](target "title")` and reference definitions `[label]: target`, outside fenced code
//! blocks and inline code spans. Targets with a scheme (`http://`, `https://`, `mailto:`, …) and
//! pure `#anchor` links are skipped; `path#anchor` is checked as `path`.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Component, Path, PathBuf};
use std::process::Command;

/// Longest README the front page may have.
const README_MAX_LINES: usize = 250;
/// The test command CI (`.ci/run`) runs as "the README's test command".
const TEST_COMMAND: &str = "cargo test --release";

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every `.md` file under docs/ (recursively), as paths relative to the root.
fn markdown_files() -> Vec<PathBuf> {
    let root = root();
    let mut files = vec![PathBuf::from("README.md")];
    let mut dirs = vec![PathBuf::from("docs")];
    while let Some(dir) = dirs.pop() {
        let entries = fs::read_dir(root.join(&dir))
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
        let mut found: Vec<PathBuf> = entries
            .map(|e| dir.join(e.expect("directory entry").file_name()))
            .collect();
        found.sort();
        for path in found {
            if root.join(&path).is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|x| x == "md") {
                files.push(path);
            }
        }
    }
    assert!(
        files.len() > 1,
        "no Markdown files under docs/: the book (docs/SUMMARY.md and its chapters) is missing"
    );
    files
}

/// One link found in a Markdown file.
#[derive(Debug)]
struct Link {
    /// The file that contains it, relative to the root.
    file: PathBuf,
    /// 1-based line number.
    line: usize,
    /// The target as written (with any `#anchor`).
    target: String,
}

impl Link {
    /// The target's path part, `#anchor` and `?query` removed, `%XX` decoded.
    fn path_part(&self) -> String {
        let end = self.target.find(['#', '?']).unwrap_or(self.target.len());
        percent_decode(&self.target[..end])
    }

    /// The target resolved against the containing file's folder, relative to the root and
    /// normalised lexically; `None` when it leaves the repository.
    fn resolved(&self) -> Option<PathBuf> {
        let base = self.file.parent().unwrap_or(Path::new(""));
        normalise(&base.join(self.path_part()))
    }

    fn describe(&self) -> String {
        format!("{}:{}: ({})", self.file.display(), self.line, self.target)
    }
}

fn percent_decode(s: &str) -> String {
    percent_encoding::percent_decode_str(s)
        .decode_utf8_lossy()
        .into_owned()
}

/// `a/./b/../c` → `a/c`; `None` if `..` climbs above the root (or the path is absolute).
fn normalise(path: &Path) -> Option<PathBuf> {
    let mut parts: Vec<&std::ffi::OsStr> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                parts.pop()?;
            }
            Component::Normal(p) => parts.push(p),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(parts.iter().collect())
}

/// A target that is not a relative path in this repository: a URL with a scheme, a
/// protocol-relative URL or a link within the same page.
fn is_external_or_anchor(target: &str) -> bool {
    if target.is_empty() || target.starts_with('#') || target.starts_with("//") {
        return true;
    }
    // A scheme: letters, digits, `+`, `-`, `.` before a colon, and the colon before any '/'.
    if let Some(colon) = target.find(':') {
        let scheme = &target[..colon];
        let slash = target.find('/').unwrap_or(usize::MAX);
        if colon < slash
            && !scheme.is_empty()
            && scheme
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic())
            && scheme
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        {
            return true;
        }
    }
    false
}

/// Removes inline code spans (`` `…` ``, any run length) from one line, so `](` inside code
/// is not read as a link.
fn strip_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let chars: Vec<char> = line.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        if chars[i] == '`' {
            let mut n = 0;
            while i + n < chars.len() && chars[i + n] == '`' {
                n += 1;
            }
            // Find the closing run of exactly n backticks.
            let mut j = i + n;
            let mut close = None;
            while j < chars.len() {
                if chars[j] == '`' {
                    let mut m = 0;
                    while j + m < chars.len() && chars[j + m] == '`' {
                        m += 1;
                    }
                    if m == n {
                        close = Some(j + m);
                        break;
                    }
                    j += m;
                } else {
                    j += 1;
                }
            }
            match close {
                Some(end) => {
                    out.push(' ');
                    i = end;
                }
                None => {
                    // An unmatched run is literal text.
                    for _ in 0..n {
                        out.push('`');
                    }
                    i += n;
                }
            }
        } else {
            out.push(chars[i]);
            i += 1;
        }
    }
    out
}

/// The target of an inline link starting just after `](`: up to the matching `)`, without
/// an optional title; `<…>` brackets removed.
fn inline_target(rest: &str) -> Option<String> {
    let rest = rest.trim_start();
    if let Some(inner) = rest.strip_prefix('<') {
        let end = inner.find('>')?;
        return Some(inner[..end].to_string());
    }
    let mut depth = 0usize;
    let mut end = None;
    for (i, c) in rest.char_indices() {
        match c {
            '(' => depth += 1,
            ')' if depth == 0 => {
                end = Some(i);
                break;
            }
            ')' => depth -= 1,
            c if c.is_whitespace() => {
                end = Some(i);
                break;
            }
            _ => {}
        }
    }
    Some(rest[..end?].to_string())
}

/// Every link and image target in one Markdown file.
fn links_in(file: &Path) -> Vec<Link> {
    let text = fs::read_to_string(root().join(file))
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
    let mut links = Vec::new();
    let mut fence: Option<String> = None;
    for (n, raw) in text.lines().enumerate() {
        let trimmed = raw.trim_start();
        // Fenced code blocks: ``` or ~~~, closed by the same kind of fence.
        if let Some(open) = &fence {
            if trimmed.starts_with(open.as_str()) {
                fence = None;
            }
            continue;
        }
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            fence = Some(trimmed[..3].to_string());
            continue;
        }
        let line = strip_code_spans(raw);
        let mut push = |target: String| {
            links.push(Link {
                file: file.to_path_buf(),
                line: n + 1,
                target,
            });
        };
        // Reference definitions: `[label]: target`.
        let t = line.trim_start();
        if t.starts_with('[')
            && !t.starts_with("[^")
            && let Some(close) = t.find("]:").filter(|&c| !t[1..c].contains(']'))
            && let Some(target) = t[close + 2..].split_whitespace().next()
        {
            push(
                target
                    .trim_start_matches('<')
                    .trim_end_matches('>')
                    .to_string(),
            );
        }
        // Inline links and images: `](target)`.
        let mut from = 0;
        while let Some(at) = line[from..].find("](") {
            let start = from + at + 2;
            if let Some(target) = inline_target(&line[start..]) {
                push(target);
            }
            from = start;
        }
    }
    links
        .into_iter()
        .filter(|l| !is_external_or_anchor(l.target.trim()))
        .collect()
}

fn all_links() -> Vec<Link> {
    let links: Vec<Link> = markdown_files().iter().flat_map(|f| links_in(f)).collect();
    assert!(
        !links.is_empty(),
        "no relative links found in README.md and docs/: the link scanner is broken"
    );
    links
}

/// Whether `git` runs here and the root is inside a work tree.
fn git_checkout() -> Result<(), String> {
    match Command::new("git")
        .args(["rev-parse", "--is-inside-work-tree"])
        .current_dir(root())
        .output()
    {
        Ok(out)
            if out.status.success() && String::from_utf8_lossy(&out.stdout).trim() == "true" =>
        {
            Ok(())
        }
        Ok(out) => Err(format!(
            "`git rev-parse --is-inside-work-tree` failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )),
        Err(e) => Err(format!("cannot run git: {e}")),
    }
}

#[test]
fn every_relative_link_and_image_exists() {
    let root = root();
    let mut broken = Vec::new();
    for link in all_links() {
        match link.resolved() {
            None => broken.push(format!("{} leaves the repository", link.describe())),
            Some(path) if !root.join(&path).exists() => broken.push(format!(
                "{} -> {} does not exist",
                link.describe(),
                path.display()
            )),
            Some(_) => {}
        }
    }
    assert!(
        broken.is_empty(),
        "{} broken relative link(s) or image(s) in README.md / docs/:\n  {}",
        broken.len(),
        broken.join("\n  ")
    );
}

#[test]
fn every_relative_link_and_image_is_tracked_by_git() {
    if let Err(why) = git_checkout() {
        eprintln!(
            "note: not checking that link targets are tracked by git ({why}); \
             every_relative_link_and_image_exists still checks that they exist"
        );
        return;
    }
    let root = root();
    let targets: BTreeSet<(PathBuf, String)> = all_links()
        .into_iter()
        .filter_map(|l| l.resolved().map(|p| (p, l.describe())))
        .collect();
    let mut untracked = Vec::new();
    let mut checked = BTreeSet::new();
    for (path, described) in &targets {
        if !root.join(path).exists() {
            continue; // reported by every_relative_link_and_image_exists
        }
        let tracked = checked.contains(path) || {
            let out = Command::new("git")
                .args(["ls-files", "--error-unmatch", "--"])
                .arg(path)
                .current_dir(&root)
                .output()
                .expect("git ran a moment ago");
            out.status.success()
        };
        if tracked {
            checked.insert(path.clone());
        } else {
            untracked.push(format!(
                "{described} -> {} exists but is not tracked by git (git add it, or check .gitignore)",
                path.display()
            ));
        }
    }
    assert!(
        untracked.is_empty(),
        "{} link target(s) in README.md / docs/ not tracked by git:\n  {}",
        untracked.len(),
        untracked.join("\n  ")
    );
}

#[test]
fn readme_is_at_most_250_lines() {
    let text = fs::read_to_string(root().join("README.md")).expect("README.md");
    let lines = text.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, more than {README_MAX_LINES}: it is the front page; \
         move details into a chapter under docs/ and link to it"
    );
}

#[test]
fn readme_keeps_the_ci_test_command() {
    let text = fs::read_to_string(root().join("README.md")).expect("README.md");
    // The command alone on its line, or followed only by a shell comment.
    let found = text.lines().map(str::trim).any(|line| {
        line == TEST_COMMAND
            || line.strip_prefix(TEST_COMMAND).is_some_and(|rest| {
                rest.starts_with(char::is_whitespace) && rest.trim_start().starts_with('#')
            })
    });
    assert!(
        found,
        "README.md has no line `{TEST_COMMAND}`: .ci/run runs \"the README's test command\", \
         so the README must keep it"
    );
}

#[test]
fn link_scanner_reads_what_markdown_means() {
    let dir = std::env::temp_dir().join(format!("refract-docs-links-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    let md = "[a](x.md) ![b](../img/p.png \"title\") [c](y.md#part) [d](#here)\n\
              [e](https://example.org/z) [f](mailto:a@b.c) `[g](in-code.md)` [h](<sp ace.md>)\n\
              ```\n[i](in-fence.md)\n```\n[ref]: z%20z.md\n[j](f(1).md)\n";
    fs::write(dir.join("t.md"), md).unwrap();
    // links_in reads relative to the root; give it an absolute path (join keeps it).
    let found: Vec<String> = links_in(&dir.join("t.md"))
        .into_iter()
        .map(|l| l.target)
        .collect();
    let _ = fs::remove_dir_all(&dir);
    assert_eq!(
        found,
        [
            "x.md",
            "../img/p.png",
            "y.md#part",
            "sp ace.md",
            "z%20z.md",
            "f(1).md"
        ],
        "the scanner's targets"
    );
    let link = |file: &str, target: &str| Link {
        file: file.into(),
        line: 1,
        target: target.into(),
    };
    assert_eq!(
        link("docs/a.md", "../screenshots/x.png#y").resolved(),
        Some("screenshots/x.png".into())
    );
    assert_eq!(
        link("README.md", "docs/z%20z.md").resolved(),
        Some("docs/z z.md".into())
    );
    assert_eq!(link("README.md", "../shared/DESIGN.md").resolved(), None);
}

/// Every `docs/NAME.md` or `README.md` a comment in `src/` or `tests/` cites exists in this
/// repository (issue 44: the design references pointed at a file outside it).
#[test]
fn documents_cited_in_code_comments_exist() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "tests"] {
        collect_rs(&root.join(dir), &mut files);
    }
    let mut missing = Vec::new();
    let mut cited = 0;
    for f in files {
        if f.ends_with("docs_links.rs") {
            continue; // its own fixtures name documents that do not exist on purpose
        }
        let text = std::fs::read_to_string(&f).expect("a source file");
        for (n, line) in text.lines().enumerate() {
            if !line.trim_start().starts_with("//") {
                continue;
            }
            for doc in cited_documents(line) {
                cited += 1;
                if !root.join(&doc).is_file() {
                    missing.push(format!("{}:{}: {doc}", f.display(), n + 1));
                }
            }
        }
    }
    assert!(
        cited > 10,
        "only {cited} citations found: is the scan broken?"
    );
    assert!(
        missing.is_empty(),
        "cited but missing:\n{}",
        missing.join("\n")
    );
}

fn collect_rs(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).expect("readable") {
        let p = e.expect("an entry").path();
        if p.is_dir() {
            collect_rs(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The `docs/NAME.md` and `README.md` paths in a line.
fn cited_documents(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, _) in line.match_indices(".md") {
        let start = line[..i]
            .rfind(|c: char| !(c.is_alphanumeric() || "_-/.".contains(c)))
            .map_or(0, |k| k + 1);
        let path = &line[start..i + 3];
        if path == "README.md" || path.starts_with("docs/") {
            out.push(path.to_owned());
        }
    }
    out
}
