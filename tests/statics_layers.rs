//! Invariant: the modules of `src/statics/` import each other without a circle — following every
//! `use` line (and every inline `super::…` / `crate::statics::…` path) from module to module,
//! no module reaches itself again. The layering is documented in `src/statics/mod.rs` and
//! docs/design.md#layering-of-statics; this test keeps it from eroding.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module path (e.g. `statics::backend::structured::kkt`) of every `.rs` file under `dir`.
fn modules(root: &Path, dir: &Path, out: &mut BTreeMap<String, PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src/statics is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            modules(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(root).expect("below src").with_extension("");
            let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if parts.last().is_some_and(|p| p == "mod") {
                parts.pop();
            }
            out.insert(parts.join("::"), path);
        }
    }
}

/// The paths named by a `use` tree such as `super::{a::{B, C}, d::E}`, flattened.
fn flatten(tree: &str, prefix: &str, out: &mut Vec<String>) {
    let tree = tree.trim();
    let Some(open) = tree.find('{') else {
        out.push(format!("{prefix}{tree}"));
        return;
    };
    let head = &tree[..open];
    let inner = &tree[open + 1..tree.rfind('}').expect("a closing brace")];
    let mut depth = 0;
    let mut start = 0;
    for (i, ch) in inner.char_indices() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                flatten(&inner[start..i], &format!("{prefix}{head}"), out);
                start = i + 1;
            }
            _ => {}
        }
    }
    if !inner[start..].trim().is_empty() {
        flatten(&inner[start..], &format!("{prefix}{head}"), out);
    }
}

/// The module a path names from module `from`: its longest prefix that is a known module.
/// `super` is the parent of the module the file defines (for `x/mod.rs` that module is `x`).
fn target(from: &str, path: &str, known: &BTreeMap<String, PathBuf>) -> Option<String> {
    let mut parts = path.split("::").map(|p| p.split_whitespace().next().unwrap_or("")).peekable();
    let mut abs: Vec<&str> = match parts.peek() {
        Some(&"crate") => {
            parts.next();
            Vec::new()
        }
        Some(&"super") | Some(&"self") => from.split("::").collect(),
        _ => return None, // an external crate or std
    };
    while let Some(&p) = parts.peek() {
        match p {
            "super" => abs.pop(),
            "self" => None,
            _ => break,
        };
        parts.next();
    }
    abs.extend(parts);
    (1..=abs.len()).rev().map(|n| abs[..n].join("::")).find(|m| known.contains_key(m))
}

#[test]
fn statics_modules_import_each_other_without_a_circle() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut known = BTreeMap::new();
    modules(&root, &root.join("statics"), &mut known);
    assert!(known.len() >= 10, "found the statics modules: {:?}", known.keys());
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, path) in &known {
        let text = std::fs::read_to_string(path).expect("a readable source file");
        // A file's own unit tests (`#[cfg(test)] mod tests { … }`, by convention at its end)
        // are not part of the layering.
        let text = text.split("#[cfg(test)]\nmod tests {").next().unwrap_or("");
        let mut named = Vec::new();
        // `use` statements, possibly over several lines.
        let mut statement: Option<String> = None;
        for line in text.lines().map(str::trim) {
            if statement.is_none() {
                let body = line.strip_prefix("pub(crate) ").or_else(|| line.strip_prefix("pub ")).unwrap_or(line);
                if let Some(tree) = body.strip_prefix("use ") {
                    statement = Some(String::new());
                    statement.as_mut().expect("just set").push_str(tree);
                }
            } else if let Some(s) = statement.as_mut() {
                s.push(' ');
                s.push_str(line);
            }
            if let Some(s) = statement.as_ref().filter(|s| s.ends_with(';')) {
                flatten(s.trim_end_matches(';'), "", &mut named);
                statement = None;
            }
        }
        // Inline paths: `super::x::…` or `crate::statics::x::…` anywhere in the code.
        for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
            for start in ["super::", "crate::statics::"] {
                for (i, _) in line.match_indices(start) {
                    let rest: String =
                        line[i..].chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
                    named.push(rest.trim_end_matches(':').to_string());
                }
            }
        }
        for p in named {
            if let Some(t) = target(module, &p, &known)
                && &t != module
            {
                edges.entry(module.clone()).or_default().insert(t);
            }
        }
    }
    // A child naming an item of its parent's front module is an edge to the parent (which
    // re-exports the child: a circle); `mod child;` declarations are not imports and are not
    // scanned. Depth-first search for a back edge.
    fn visit(
        m: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for t in edges.get(m).into_iter().flatten() {
            match state.get(t.as_str()).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|s| s == t).expect("on the stack");
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(t.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(t, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in known.keys() {
        if state.get(m.as_str()).copied().unwrap_or(0) == 0
            && let Some(cycle) = visit(m, &edges, &mut state, &mut Vec::new())
        {
            panic!("import circle: {}\nedges: {edges:#?}", cycle.join(" → "));
        }
    }
    // The leaf vocabulary and the backends stay where the layering puts them.
    let reaches = |from: &str| edges.get(from).cloned().unwrap_or_default();
    assert!(reaches("statics::problem").is_empty(), "problem.rs is a leaf: {:?}", reaches("statics::problem"));
    for (m, ts) in &edges {
        if m == "statics::backend" || m.starts_with("statics::backend::") {
            for t in ts {
                assert!(
                    t == "statics::backend" || t.starts_with("statics::backend::") || t == "statics::problem",
                    "{m} imports {t}: the backends import only the vocabulary (problem.rs)"
                );
            }
        }
    }
}
