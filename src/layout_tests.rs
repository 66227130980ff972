//! The layers of `src/` import one way: the graph of `use crate::` edges
//! between the top-level modules (a folder counts as one module) has no cycle.

use std::collections::{BTreeMap, BTreeSet};
use std::string::{String, ToString};
use std::vec::Vec;

/// Top-level module of every library source file (tests excluded), with its
/// code stripped of comments and test modules.
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
            let rel = path.strip_prefix(&root).unwrap().to_string_lossy().into_owned();
            if !rel.ends_with(".rs") || rel.contains("tests") || rel == "lib.rs" {
                continue;
            }
            let top = rel.split(['/', '.']).next().unwrap().to_string();
            let text = std::fs::read_to_string(&path).unwrap();
            // Test modules may reach anywhere; comments name modules without using them.
            let code = text.split("#[cfg(test)]\nmod ").next().unwrap();
            let code: String = code
                .lines()
                .map(|l| l.split("//").next().unwrap())
                .collect::<Vec<_>>()
                .join("\n");
            out.push((top, code));
        }
    }
    out
}

/// `a -> b` when a file of `a` names `crate::b` (also `crate::{b, ...}`).
fn edges() -> BTreeMap<String, BTreeSet<String>> {
    let files = sources();
    let tops: BTreeSet<String> = files.iter().map(|(t, _)| t.clone()).collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = tops.iter().map(|t| (t.clone(), BTreeSet::new())).collect();
    for (top, code) in &files {
        for (i, _) in code.match_indices("crate::") {
            let rest = &code[i + "crate::".len()..];
            let names: Vec<&str> = match rest.strip_prefix('{') {
                Some(group) => group.split('}').next().unwrap().split(',').collect(),
                None => std::vec![rest],
            };
            for name in names {
                let name: String = name
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if tops.contains(&name) && name != *top {
                    graph.get_mut(top).unwrap().insert(name);
                }
            }
        }
    }
    graph
}

/// What is left after repeatedly removing modules that import nothing left
/// (Kahn): empty exactly when the graph has no cycle.
fn in_cycles(mut left: BTreeMap<String, BTreeSet<String>>) -> BTreeMap<String, BTreeSet<String>> {
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
    let graph = edges();
    // The layers the architecture promises: a sanity check that the parser sees edges.
    assert!(graph["render"].contains("scene"), "{graph:?}");
    assert!(graph["scene"].contains("number"), "{graph:?}");
    let left = in_cycles(graph.clone());
    assert!(left.is_empty(), "import cycle among these modules of src/: {left:?}");
}

#[test]
fn the_cycle_check_sees_a_cycle() {
    // A two-module loop beside a leaf: exactly the loop is reported.
    let mut left: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    left.insert("a".into(), ["b".to_string()].into());
    left.insert("b".into(), ["a".to_string()].into());
    left.insert("c".into(), BTreeSet::new());
    assert_eq!(in_cycles(left).keys().collect::<Vec<_>>(), ["a", "b"]);
}
