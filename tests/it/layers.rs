//! Invariant: the crate is layered. Every module of `src/` imports only modules of lower layers
//! (the table [`LAYERS`], which docs/design.md shows word for word), never a module of its own
//! layer or above, and the files of one folder import each other without a circle. Arrows are
//! the `use` lines and the inline `crate::…` / `super::…` paths of the code (not comments, not
//! a file's own `#[cfg(test)] mod tests`); a front module's re-exports (`pub use child::…` in a
//! `mod.rs`) are the folder's face, not an import of its code. Inside `src/statics/` the rule is
//! stricter (docs/design.md, "Layering of statics"): no child imports the front module at all,
//! the vocabulary (`problem.rs`) imports no sibling and the backends import only it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers, lowest first: (layer, top-level modules, what they hold).
const LAYERS: [(u8, &[&str], &str); 16] = [
    (1, &["geometry", "optimise"], "meshes, polygons, plane cuts, tolerances; argmin's searches"),
    (2, &["model"], "scenes, blocks, materials, loads, validated assemblies"),
    (3, &["history"], "replaying a design's cut history"),
    (4, &["interfaces"], "contact detection"),
    (5, &["statics"], "equilibrium, load factor, mechanisms, the rate problem"),
    (6, &["dynamics"], "the drop test: rapier, and the exact-contact engine"),
    (7, &["pipeline"], "cuts → blocks → interfaces → statics, with memory between runs"),
    (8, &["stability"], "load factor and worst direction, the kinematic verdict"),
    (9, &["studies"], "thresholds by bisection, assembly sequences"),
    (10, &["synthesis"], "generated decompositions, repair, props"),
    (11, &["io"], "scene formats in and out"),
    (12, &["report"], "JSON, text and compas reports of results"),
    (13, &["viz"], "palette, glTF, plots, the HTML report"),
    (14, &["ecs"], "bevy plugins (feature `ecs`, default)"),
    (15, &["viewer"], "the interactive viewer (feature `viewer`)"),
    (16, &["cli"], "the command line"),
];

/// The module path (`statics::backend::structured::kkt`) → source text of every `.rs` file
/// below `dir`; `lib.rs` and `main.rs` are the crate root and not listed.
fn sources(root: &Path, dir: &Path, out: &mut BTreeMap<String, String>) {
    for entry in std::fs::read_dir(dir).expect("src is readable") {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            sources(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(root).expect("below src").with_extension("");
            let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if parts.last().is_some_and(|p| p == "mod") {
                parts.pop();
            }
            if parts == ["lib"] || parts == ["main"] {
                continue;
            }
            out.insert(parts.join("::"), std::fs::read_to_string(&path).expect("a readable source file"));
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
    let (mut depth, mut start) = (0, 0);
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
fn target(from: &str, path: &str, known: &BTreeMap<String, String>) -> Option<String> {
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

/// Whether `module` is a folder's front module (a `mod.rs`): its children are the known
/// modules one level below it.
fn is_front(module: &str, known: &BTreeMap<String, String>) -> bool {
    known.keys().any(|k| k.strip_prefix(module).is_some_and(|rest| rest.starts_with("::")))
}

/// The paths a file's code names: `use` statements (over several lines) and inline
/// `crate::` / `super::` paths; with `reexports` false, a front module's `pub use` lines are left
/// out.
fn named_paths(text: &str, reexports: bool) -> Vec<String> {
    let text = text.split("#[cfg(test)]\nmod tests {").next().unwrap_or("");
    let mut named = Vec::new();
    let mut statement: Option<(String, bool)> = None;
    for line in text.lines().map(str::trim).filter(|l| !l.starts_with("//")) {
        if statement.is_none() {
            let public = line.starts_with("pub use ") || line.starts_with("pub(crate) use ");
            let body = line.strip_prefix("pub(crate) ").or_else(|| line.strip_prefix("pub ")).unwrap_or(line);
            if let Some(tree) = body.strip_prefix("use ") {
                statement = Some((tree.to_string(), public));
                if !tree.ends_with(';') {
                    continue;
                }
            }
        } else if let Some((s, _)) = statement.as_mut() {
            s.push(' ');
            s.push_str(line);
        }
        match statement.take() {
            Some((s, public)) if s.ends_with(';') => {
                if reexports || !public {
                    flatten(s.trim_end_matches(';'), "", &mut named);
                }
            }
            Some(open) => statement = Some(open),
            None => {
                for start in ["super::", "crate::"] {
                    for (i, _) in line.match_indices(start) {
                        let rest: String =
                            line[i..].chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
                        named.push(rest.trim_end_matches(':').to_string());
                    }
                }
            }
        }
    }
    named
}

/// Module → the modules its code imports (itself and its own children left out).
fn edges(known: &BTreeMap<String, String>, reexports: bool) -> BTreeMap<String, BTreeSet<String>> {
    let mut out: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, text) in known {
        let front = is_front(module, known);
        for p in named_paths(text, reexports || !front) {
            if let Some(t) = target(module, &p, known)
                && &t != module
            {
                out.entry(module.clone()).or_default().insert(t);
            }
        }
    }
    out
}

fn layer_of(top: &str) -> Option<u8> {
    LAYERS.iter().find(|(_, ms, _)| ms.contains(&top)).map(|(l, _, _)| *l)
}

/// Every arrow that goes to a higher layer, or sideways to another module of the same layer.
fn layer_violations(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let top = |m: &str| m.split("::").next().unwrap_or(m).to_string();
    let mut out = Vec::new();
    for (from, targets) in edges {
        let (a, fa) = (top(from), layer_of(&top(from)));
        for to in targets {
            let (b, fb) = (top(to), layer_of(&top(to)));
            match (fa, fb) {
                (None, _) => out.push(format!("{from}: module '{a}' is in no layer of the table")),
                (_, None) => out.push(format!("{to}: module '{b}' is in no layer of the table")),
                (Some(x), Some(y)) if y > x || (y == x && a != b) => {
                    out.push(format!("{from} (layer {x}) imports {to} (layer {y})"))
                }
                _ => {}
            }
        }
    }
    out
}

/// A circle among the files of one folder (edges between siblings and with the folder's front
/// module), if any.
fn folder_circle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    let parent = |m: &str| m.rsplit_once("::").map(|(p, _)| p.to_string()).unwrap_or_default();
    let same_folder = |a: &str, b: &str| parent(a) == parent(b) || parent(a) == b || parent(b) == a;
    fn visit(
        m: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        keep: &dyn Fn(&str, &str) -> bool,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(m.to_string(), 1);
        stack.push(m.to_string());
        for t in edges.get(m).into_iter().flatten().filter(|t| keep(m, t)) {
            match state.get(t.as_str()).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|s| s == t).expect("on the stack");
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(t.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(t, edges, keep, state, stack) {
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
    for m in edges.keys() {
        if state.get(m.as_str()).copied().unwrap_or(0) == 0
            && let Some(c) = visit(m, edges, &same_folder, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

fn crate_sources() -> BTreeMap<String, String> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut known = BTreeMap::new();
    sources(&root, &root, &mut known);
    known
}

#[test]
fn every_module_imports_only_lower_layers_without_a_circle() {
    let known = crate_sources();
    assert!(known.len() >= 100, "found the modules: {}", known.len());
    let tops: BTreeSet<&str> = known.keys().map(|k| k.split("::").next().unwrap_or(k)).collect();
    for t in &tops {
        assert!(layer_of(t).is_some(), "module '{t}' is in no layer of the table");
    }
    let e = edges(&known, false);
    let violations = layer_violations(&e);
    assert!(violations.is_empty(), "arrows against the layers:\n{}", violations.join("\n"));
    if let Some(c) = folder_circle(&e) {
        panic!("import circle between files of a folder: {}", c.join(" → "));
    }
}

#[test]
fn statics_front_module_vocabulary_and_backends_stay_in_place() {
    let known = crate_sources();
    let e = edges(&known, true);
    let statics = |m: &String| m == "statics" || m.starts_with("statics::");
    for (m, ts) in e.iter().filter(|(m, _)| statics(m) && m.as_str() != "statics") {
        assert!(!ts.contains("statics"), "{m} imports the front module statics/mod.rs");
    }
    let inside = |m: &str| e.get(m).into_iter().flatten().filter(|t| statics(t)).cloned().collect::<Vec<_>>();
    assert!(inside("statics::problem").is_empty(), "problem.rs is a leaf of statics: {:?}", inside("statics::problem"));
    for (m, _) in e.iter().filter(|(m, _)| m.as_str() == "statics::backend" || m.starts_with("statics::backend::")) {
        for t in inside(m) {
            assert!(
                t == "statics::backend" || t.starts_with("statics::backend::") || t == "statics::problem",
                "{m} imports {t}: the backends import only the vocabulary (problem.rs)"
            );
        }
    }
}

/// The checker itself: an arrow planted up the layers, one planted sideways and a planted
/// circle between two files of a folder are each found.
#[test]
fn a_planted_arrow_or_circle_is_found() {
    let mut known = BTreeMap::new();
    known.insert("geometry".to_string(), "pub use mesh::Mesh;\n".to_string());
    known.insert("geometry::mesh".to_string(), "use crate::statics::Verdict;\n".to_string());
    known.insert("statics".to_string(), "pub(crate) use crate::geometry::mesh;\n".to_string());
    known.insert("optimise".to_string(), "fn f() { crate::geometry::mesh::g() }\n".to_string());
    let v = layer_violations(&edges(&known, false));
    assert!(v.iter().any(|s| s.contains("geometry::mesh (layer 1) imports statics (layer 5)")), "{v:?}");
    assert!(v.iter().any(|s| s.contains("optimise (layer 1) imports geometry::mesh (layer 1)")), "{v:?}");
    assert_eq!(v.len(), 2, "the arrow down (statics → geometry) is allowed: {v:?}");

    let mut circle = BTreeMap::new();
    circle.insert("model".to_string(), "pub use a::A;\n".to_string());
    circle.insert("model::a".to_string(), "use super::b::B;\n".to_string());
    circle.insert("model::b".to_string(), "use super::{c::C, a::A};\n".to_string());
    circle.insert("model::c".to_string(), String::new());
    let c = folder_circle(&edges(&circle, false)).expect("the planted circle is found");
    assert!(c.join(" ").contains("model::a") && c.join(" ").contains("model::b"), "{c:?}");
    circle.insert("model::b".to_string(), "use super::c::C;\n".to_string());
    assert_eq!(folder_circle(&edges(&circle, false)), None, "no circle once b stops importing a");
}

/// docs/design.md shows the same table, row for row.
#[test]
fn the_design_doc_shows_the_layer_table() {
    let doc = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/design.md"))
        .expect("docs/design.md is readable");
    let mut table = String::from("| layer | modules | what they hold |\n|---|---|---|\n");
    for (l, ms, what) in LAYERS {
        table.push_str(&format!(
            "| {l} | {} | {what} |\n",
            ms.iter().map(|m| format!("`{m}`")).collect::<Vec<_>>().join(", ")
        ));
    }
    assert!(doc.contains(&table), "docs/design.md's layer table differs from the test's; it should read:\n{table}");
}
