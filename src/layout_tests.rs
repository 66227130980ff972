//! The modules of `src/` import one way, at two grains: among the top-level
//! modules (a folder counts as one module), and among all modules, every file
//! one (`number/mod.rs` is `number`, `number/film.rs` is `number::film`).

use std::collections::{BTreeMap, BTreeSet};
use std::string::{String, ToString};
use std::vec::Vec;

type Graph = BTreeMap<String, BTreeSet<String>>;

/// Every library source file (tests and `lib.rs` excluded) as its module path
/// (`number::film`) and its code stripped of comments and test modules.
fn sources() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    let mut stack = std::vec![root.clone()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            let rel = path.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
            if !rel.ends_with(".rs") || rel.contains("tests") || rel == "lib.rs" {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((module_path(&rel), strip(&text)));
        }
    }
    out
}

/// `number/mod.rs` -> `number`, `number/film.rs` -> `number::film`.
fn module_path(rel: &str) -> String {
    let rel = rel.strip_suffix(".rs").unwrap();
    let rel = rel.strip_suffix("/mod").unwrap_or(rel);
    rel.replace('/', "::")
}

/// Code without test modules (they may reach anywhere) and line comments
/// (they name modules without using them).
fn strip(text: &str) -> String {
    let code = text.split("#[cfg(test)]\nmod ").next().unwrap();
    code.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The paths a `use` tree or path starting at `rest` names, each as its
/// segments: `a::{b, c::d}` gives `a::b` and `a::c::d`.
fn paths(rest: &str) -> Vec<Vec<String>> {
    let name: String = rest.trim_start().chars().take_while(|&c| is_ident(c)).collect();
    let after = &rest.trim_start()[name.len()..];
    if name.is_empty() {
        let Some(group) = rest.trim_start().strip_prefix('{') else {
            return Vec::new();
        };
        // Split the group at its top-level commas.
        let (mut depth, mut start, mut out) = (0, 0, Vec::new());
        for (i, c) in group.char_indices() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    out.extend(paths(&group[start..i]));
                    return out;
                }
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    out.extend(paths(&group[start..i]));
                    start = i + 1;
                }
                _ => {}
            }
        }
        return out;
    }
    match after.strip_prefix("::") {
        Some(tail) => {
            let mut out = paths(tail);
            if out.is_empty() {
                out.push(Vec::new());
            }
            for p in &mut out {
                p.insert(0, name.clone());
            }
            out
        }
        None => std::vec![std::vec![name]],
    }
}

/// `a -> b` when a file of module `a` names a path into module `b`: through
/// `crate::`, `super::`, `self::`, or a child module's name. A path resolves to
/// its longest prefix that is a module.
fn edges_of(files: &[(String, String)]) -> Graph {
    let modules: BTreeSet<String> = files.iter().map(|(m, _)| m.clone()).collect();
    let mut graph: Graph = modules.iter().map(|m| (m.clone(), BTreeSet::new())).collect();
    for (module, code) in files {
        let own: Vec<String> = module.split("::").map(str::to_string).collect();
        // Children declared here are in scope by their bare names.
        let children: Vec<String> = modules
            .iter()
            .filter_map(|m| m.strip_prefix(&std::format!("{module}::")))
            .filter(|c| !c.contains("::"))
            .map(str::to_string)
            .collect();
        let mut starts: Vec<(Vec<String>, usize)> = Vec::new();
        for (i, _) in code.match_indices("::") {
            let before: String = code[..i]
                .chars()
                .rev()
                .take_while(|&c| is_ident(c))
                .collect::<Vec<_>>()
                .into_iter()
                .rev()
                .collect();
            let head_at = i - before.len();
            // Only the head of a path: not `x::crate`, not `fooself`.
            if code[..head_at].ends_with("::") {
                continue;
            }
            let base = match before.as_str() {
                "crate" => Vec::new(),
                "self" => own.clone(),
                "super" => {
                    // `super::super::...` climbs once per `super`.
                    let (mut at, mut up) = (i + 2, 1);
                    while code[at..].starts_with("super::") {
                        at += "super::".len();
                        up += 1;
                    }
                    starts.push((own[..own.len().saturating_sub(up)].to_vec(), at));
                    continue;
                }
                child if children.iter().any(|c| c == child) => {
                    let mut b = own.clone();
                    b.push(child.to_string());
                    b
                }
                _ => continue,
            };
            starts.push((base, i + 2));
        }
        for (base, at) in starts {
            let mut found = paths(&code[at..]);
            if found.is_empty() {
                found.push(Vec::new());
            }
            for tail in found {
                let full: Vec<String> = base.iter().cloned().chain(tail).collect();
                let target = (1..=full.len())
                    .rev()
                    .map(|n| full[..n].join("::"))
                    .find(|p| modules.contains(p));
                if let Some(target) = target {
                    if target != *module {
                        graph.get_mut(module).unwrap().insert(target);
                    }
                }
            }
        }
    }
    graph
}

/// The same graph with every module folded into its top-level module.
fn top_level(graph: &Graph) -> Graph {
    let top = |m: &str| m.split("::").next().unwrap().to_string();
    let mut out: Graph = BTreeMap::new();
    for (from, to) in graph {
        let entry = out.entry(top(from)).or_default();
        entry.extend(to.iter().map(|t| top(t)).filter(|t| *t != top(from)));
    }
    out
}

/// What is left after repeatedly removing modules that import nothing left
/// (Kahn): empty exactly when the graph has no cycle.
fn in_cycles(mut left: Graph) -> Graph {
    while let Some(leaf) = left.iter().find(|(_, to)| to.is_empty()).map(|(m, _)| m.clone()) {
        left.remove(&leaf);
        for to in left.values_mut() {
            to.remove(&leaf);
        }
    }
    left
}

#[test]
fn module_imports_form_no_cycle() {
    let graph = top_level(&edges_of(&sources()));
    // The layers the architecture promises: a sanity check that the parser sees edges.
    assert!(graph["render"].contains("scene"), "{graph:?}");
    assert!(graph["scene"].contains("number"), "{graph:?}");
    let left = in_cycles(graph.clone());
    assert!(left.is_empty(), "import cycle among these modules of src/: {left:?}");
}

#[test]
fn file_imports_form_no_cycle() {
    let graph = edges_of(&sources());
    // Edges inside folders are seen: through `crate::`, and a child's bare name.
    assert!(graph["number::fixed"].contains("number::film"), "{graph:?}");
    assert!(graph["number"].contains("number::scalar"), "{graph:?}");
    assert!(graph["render::trace"].contains("render::cull"), "{graph:?}");
    let left = in_cycles(graph.clone());
    assert!(left.is_empty(), "import cycle among these files of src/: {left:?}");
}

#[test]
fn the_cycle_check_sees_a_cycle() {
    // A two-module loop beside a leaf: exactly the loop is reported.
    let mut left = Graph::new();
    left.insert("a".into(), ["b".to_string()].into());
    left.insert("b".into(), ["a".to_string()].into());
    left.insert("c".into(), BTreeSet::new());
    assert_eq!(in_cycles(left).keys().collect::<Vec<_>>(), ["a", "b"]);
}

#[test]
fn the_edge_parser_sees_loops_through_a_folder() {
    let file = |m: &str, code: &str| (m.to_string(), strip(code));
    // The loop this layout had: the trait's file used the film map, which used
    // the trait's file; plus every other way to name a module.
    let files = [
        file("n", "pub use film::Map;\nmod film;\nmod wide;\n"),
        file("n::film", "use crate::n::{shr, wide::{mul, div}};\n"),
        file("n::wide", "fn f() -> super::super::g::G { self::h() }\n"),
        file(
            "g",
            "// crate::n::film in a comment is no edge\n#[cfg(test)]\nmod tests { use crate::n; }\n",
        ),
    ];
    let graph = edges_of(&files);
    assert_eq!(graph["n"], ["n::film".to_string()].into());
    assert_eq!(graph["n::film"], ["n".to_string(), "n::wide".to_string()].into());
    assert_eq!(graph["n::wide"], ["g".to_string()].into());
    assert!(graph["g"].is_empty());
    assert_eq!(in_cycles(graph.clone()).keys().collect::<Vec<_>>(), ["n", "n::film"]);
    // Folded to the top level the folder's loop vanishes and no other appears.
    assert!(in_cycles(top_level(&graph)).is_empty());
}
