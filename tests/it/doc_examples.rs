//! Invariant: every command example of the docs runs and prints what the docs say.
//!
//! The `console` blocks of README.md and docs/**/*.md are trycmd test cases, run in place: each
//! `$ voussoir …` line runs the binary from a scratch folder that sees the repository's `assets/`
//! (so the docs' paths resolve and the files the examples write land there, not in the checkout),
//! its output (stdout and stderr) must match the lines under it — `...` a run of lines, `[..]`
//! part of a line, for timings, paths and long tables — and its exit code the `? N` line (0 when
//! there is none). The docs of one file run in order in one folder: a later example may read what
//! an earlier one wrote. `TRYCMD=overwrite cargo test --test it doc_examples` writes the actual
//! output back into the docs.
//!
//! Coverage: a fenced shell block (` ```sh `, `bash`, `shell`, `console`, unlabelled) holding a
//! line that starts with `voussoir` or `cargo run` (after an optional `$ `) is either a trycmd
//! case — a `$ voussoir …` line in a `console` (or `trycmd`, or unlabelled) block that trycmd
//! reads, so not `ignore`d and not indented — or one of [`NOT_RUN`], which names the command and
//! why the tests cannot run it. A ` ```text ` block may show a `voussoir` line only as a usage
//! synopsis (a placeholder in capitals or an option in brackets): a runnable command there would
//! be hidden from the tests.

use std::path::{Path, PathBuf};

/// The commands of the docs that the tests do not run: (file, command, why).
const NOT_RUN: &[(&str, &str, &str)] = &[
    (
        "README.md",
        "cargo run --release",
        "the set-up command: a release build of the crate (minutes on two cores); what it runs, \
         the default scene's analysis, is tests/it/cli.rs's default_scene_stands_with_exit_code_0",
    ),
    (
        "README.md",
        "cargo run --release --features viewer -- view",
        "the viewer opens a window: it needs a display and the viewer feature's build \
         (tests/viewer_render.rs runs it under Xvfb)",
    ),
    (
        "docs/benchmarks.md",
        "cargo run --release --example timing",
        "an example program that times a release build: what it prints is this machine's speed",
    ),
];

/// The repository root (the integration tests' working directory too).
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every `.md` under docs/, relative to the root, sorted.
fn doc_files() -> Vec<PathBuf> {
    let mut files = vec![PathBuf::from("README.md")];
    let mut dirs = vec![PathBuf::from("docs")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(root().join(&dir)).expect("docs/ is readable") {
            let path = dir.join(entry.expect("a directory entry").file_name());
            if root().join(&path).is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// One fenced code block of a markdown file.
#[derive(Debug)]
struct Block {
    /// 1-based line of the opening fence.
    line: usize,
    /// The info string's first word (`sh`, `console`, …; empty when unlabelled).
    lang: String,
    /// Whether trycmd runs it: a backtick fence at the start of the line, labelled `console` or
    /// `trycmd` (or not at all), without the `ignore` attribute.
    runnable: bool,
    lines: Vec<String>,
}

/// The fenced blocks of `text` (backtick or tilde fences of three or more, as CommonMark).
fn fenced_blocks(text: &str) -> Vec<Block> {
    let mut blocks = Vec::new();
    let mut open: Option<(String, Block)> = None;
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let fence_len = trimmed.chars().take_while(|&c| c == '`' || c == '~').count();
        let fence = &trimmed[..fence_len];
        let is_fence = fence_len >= 3 && fence.chars().all(|c| c == fence.chars().next().unwrap());
        match open.take() {
            Some((opening, block))
                if is_fence && fence.starts_with(&opening) && trimmed[fence_len..].trim().is_empty() =>
            {
                blocks.push(block)
            }
            Some((opening, mut block)) => {
                block.lines.push(line.to_string());
                open = Some((opening, block));
            }
            None if is_fence => {
                let info = trimmed[fence_len..].trim();
                let mut words = info.split(|c: char| c == ',' || c.is_whitespace()).filter(|w| !w.is_empty());
                let lang = words.next().unwrap_or("").to_string();
                let ignored = words.any(|w| w == "ignore");
                let runnable = fence.starts_with("```")
                    && line.starts_with('`')
                    && matches!(lang.as_str(), "" | "console" | "trycmd")
                    && !ignored;
                open = Some((fence.to_string(), Block { line: i + 1, lang, runnable, lines: Vec::new() }));
            }
            None => {}
        }
    }
    blocks
}

/// The command a line of a shell block shows: without a `$ ` prompt and a trailing `# comment`.
fn command(line: &str) -> &str {
    let line = line.trim_start();
    let line = line.strip_prefix("$ ").unwrap_or(line);
    line.split(" #").next().unwrap_or(line).trim_end()
}

/// Whether a command runs voussoir (the installed binary or through cargo).
fn is_voussoir(command: &str) -> bool {
    command == "voussoir" || command.starts_with("voussoir ") || command.starts_with("cargo run")
}

/// Whether a line reads as a usage synopsis: a placeholder in capitals (`SCENE`, `OUT.json`) or
/// an option in brackets.
fn is_synopsis(line: &str) -> bool {
    line.contains('[')
        || line.split(|c: char| !c.is_alphanumeric()).any(|w| w.len() >= 3 && w.chars().all(|c| c.is_ascii_uppercase()))
}

/// The trycmd commands of a runnable block: its `$ voussoir …` lines.
fn trycmd_commands(block: &Block) -> impl Iterator<Item = &str> {
    block.lines.iter().filter_map(|l| l.strip_prefix("$ ")).filter(|c| c.starts_with("voussoir"))
}

/// Why each `voussoir`/`cargo run` line of a file's blocks is not covered, as messages.
fn uncovered(file: &Path, text: &str) -> Vec<String> {
    let mut problems = Vec::new();
    for block in fenced_blocks(text) {
        let at = format!("{}:{} (```{})", file.display(), block.line, block.lang);
        match block.lang.as_str() {
            "text" => {
                for line in block.lines.iter().filter(|l| is_voussoir(command(l)) && !is_synopsis(l)) {
                    problems
                        .push(format!("{at}: `{}` is a command in a text block: make it a console block", line.trim()));
                }
            }
            "" | "sh" | "bash" | "shell" | "zsh" | "console" | "trycmd" => {
                let run: Vec<&str> = if block.runnable { trycmd_commands(&block).collect() } else { Vec::new() };
                let mut after_command = false;
                for line in &block.lines {
                    let cmd = command(line);
                    after_command |= block.runnable && line.starts_with("$ ");
                    // In a block trycmd runs, what follows a command is its expected output.
                    let output = after_command && !line.starts_with("$ ");
                    let covered = run.contains(&line.strip_prefix("$ ").unwrap_or(""))
                        || output
                        || NOT_RUN.iter().any(|(f, c, _)| Path::new(f) == file && *c == cmd);
                    if is_voussoir(cmd) && !covered {
                        problems.push(format!(
                            "{at}: `{cmd}` is run by no test: write it as `$ {cmd}` in a ```console block with its \
                             output, or list it in NOT_RUN with the reason"
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    problems
}

#[test]
fn every_command_in_a_shell_block_of_the_docs_is_a_trycmd_case_or_listed() {
    let mut problems = Vec::new();
    let mut cases = 0;
    let mut listed_seen = vec![false; NOT_RUN.len()];
    for file in doc_files() {
        let text = std::fs::read_to_string(root().join(&file)).expect("the doc is readable");
        problems.extend(uncovered(&file, &text));
        for block in fenced_blocks(&text) {
            cases += if block.runnable { trycmd_commands(&block).count() } else { 0 };
            for line in &block.lines {
                for (seen, (f, c, _)) in listed_seen.iter_mut().zip(NOT_RUN) {
                    *seen |= Path::new(f) == file && command(line) == *c;
                }
            }
        }
    }
    for (seen, (f, c, _)) in listed_seen.iter().zip(NOT_RUN) {
        if !seen {
            problems.push(format!("NOT_RUN lists `{c}` in {f}, which no longer shows it: drop it from the list"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(cases >= 20, "the docs' console blocks hold {cases} commands: fewer than the docs show");
}

/// The checker itself: what it accepts and what it refuses, on small documents.
#[test]
fn the_coverage_check_tells_cases_from_uncovered_commands() {
    let doc = Path::new("doc.md");
    let ok = "```console\n$ voussoir analyze x.json\nSTANDS\n```\n\n```text\nvoussoir analyze SCENE [--json OUT]\n```\n\
              ```pycon\n>>> voussoir.analyze(s)\n```\n";
    assert_eq!(uncovered(doc, ok), Vec::<String>::new());
    for bad in [
        "```sh\nvoussoir analyze x.json\n```\n",
        "```bash\n$ voussoir analyze x.json\n```\n",
        "```\ncargo run --release -- analyze x.json\n```\n",
        "```console,ignore\n$ voussoir analyze x.json\n```\n",
        "- a list item\n  ```console\n  $ voussoir analyze x.json\n  ```\n",
        "```console\n$ cargo run --release -- analyze x.json\n```\n",
        "```text\nvoussoir analyze assets/x.json --mu 0.5\n```\n",
        "~~~console\n$ voussoir analyze x.json\n~~~\n",
    ] {
        assert_eq!(uncovered(doc, bad).len(), 1, "{bad}");
    }
    // A listed exception is covered only in its own file.
    assert!(uncovered(Path::new("README.md"), "```sh\ncargo run --release      # the set-up\n```\n").is_empty());
    assert_eq!(uncovered(doc, "```sh\ncargo run --release\n```\n").len(), 1);
}

/// A folder of trycmd cases in the tests' scratch space, removed when dropped: each doc with
/// commands linked in under a flat name (`docs/guide/01-x.md` → `docs-guide-01-x.md`), beside
/// `NAME.in`, a link to a template holding only a link to the repository's `assets/`, and an
/// empty `NAME.out`, which turns trycmd's sandbox on: each doc runs in a fresh temporary copy of
/// the template.
struct CaseDir(PathBuf);

impl CaseDir {
    fn new(docs: &[PathBuf]) -> Self {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("doc_examples-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let template = dir.join("template");
        std::fs::create_dir_all(&template).expect("the scratch folder");
        let link = |target: &Path, at: &Path| std::os::unix::fs::symlink(target, at).expect("a symbolic link");
        link(&root().join("assets"), &template.join("assets"));
        for doc in docs {
            let name = doc.to_string_lossy().replace('/', "-");
            let case = dir.join(&name);
            link(&root().join(doc), &case);
            link(&template, &case.with_extension("in"));
            std::fs::create_dir(case.with_extension("out")).expect("the case's .out folder");
        }
        Self(dir)
    }
}

impl Drop for CaseDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn the_docs_command_examples_print_what_they_show() {
    let docs: Vec<PathBuf> = doc_files()
        .into_iter()
        .filter(|f| {
            let text = std::fs::read_to_string(root().join(f)).expect("the doc is readable");
            fenced_blocks(&text).iter().any(|b| b.runnable && trycmd_commands(b).next().is_some())
        })
        .collect();
    for expected in ["README.md", "docs/guide/01-does-it-stand.md", "docs/guide/04-motion.md"] {
        assert!(docs.contains(&PathBuf::from(expected)), "{expected} has command examples to run");
    }
    let cases = CaseDir::new(&docs);
    trycmd::TestCases::new()
        .register_bin("voussoir", trycmd::cargo::cargo_bin!("voussoir"))
        .case(cases.0.join("*.md"))
        .run();
}
