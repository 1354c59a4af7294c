//! The documentation's rules, held against the files: the README stays short and links every
//! guide, every relative link resolves, and no user-facing text cites an issue number, which
//! its readers cannot see.

use std::path::{Path, PathBuf};

const README_MAX_LINES: usize = 250;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The guides: every Markdown file directly under docs/.
fn guides() -> Vec<PathBuf> {
    let mut guides: Vec<_> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ exists")
        .map(|entry| entry.expect("docs/ lists").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    guides.sort();
    guides
}

/// What users read: the README, the guides, the other READMEs and the C header.
fn user_facing() -> Vec<PathBuf> {
    let root = root();
    let mut files = vec![root.join("README.md"), root.join("include/patchex.h")];
    files.extend(guides());
    for readme in [
        "plugin-unreal/README.md",
        "assets/README.md",
        "crates/patchex-scene/README.md",
    ] {
        files.push(root.join(readme));
    }
    files
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The targets of `[text](target)` links that are not web addresses or anchors, without their
/// anchors.
fn relative_links(text: &str) -> Vec<&str> {
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            let target = &rest[..rest.find(')')?];
            let target = target.split('#').next().unwrap_or_default();
            let external = target.contains("://") || target.starts_with("mailto:");
            (!target.is_empty() && !external).then_some(target)
        })
        .collect()
}

#[test]
fn the_readme_is_short_and_links_every_guide() {
    let readme = read(&root().join("README.md"));
    let lines = readme.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines, at most {README_MAX_LINES}"
    );
    let links = relative_links(&readme);
    for guide in guides() {
        let name = format!("docs/{}", guide.file_name().unwrap().to_string_lossy());
        assert!(
            links.contains(&name.as_str()),
            "README.md does not link {name}"
        );
    }
}

#[test]
fn every_relative_link_resolves() {
    for file in user_facing() {
        let text = read(&file);
        let dir = file.parent().unwrap();
        for target in relative_links(&text) {
            assert!(
                dir.join(target).exists(),
                "{}: link to {target}, which does not exist",
                file.display()
            );
        }
    }
}

#[test]
fn no_user_facing_text_cites_an_issue() {
    for file in user_facing() {
        let text = read(&file).to_lowercase();
        for (at, _) in text.match_indices("issue") {
            let after = text[at + "issue".len()..].trim_start_matches([' ', '#']);
            assert!(
                !after.starts_with(|c: char| c.is_ascii_digit()),
                "{} cites an issue number: {:?}",
                file.display(),
                &text[at..(at + 16).min(text.len())]
            );
        }
    }
}
