//! The house's shape, checked on the sources: modules import one another one way (no cycle among
//! the modules of one folder, at any depth), the formats floor (`io`) stands below the algorithms,
//! and the command-line layer is the binary's, not the library's.
//!
//! Imports are read from the sources: every `crate::` and `super::` path (in `use` trees, grouped
//! ones included, and inline), outside comments and outside test code (files named `tests.rs` and
//! `#[cfg(test)]` modules), resolved to the deepest module that has a file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's rooms above the ground floor: the algorithms (and `export`, which writes files
/// that carry computed results and so stands above both the formats and the algorithms). The
/// ground floor imports none of them.
const ALGORITHMS: [&str; 17] = [
    "balance",
    "compare",
    "compartments",
    "conformations",
    "diff",
    "expected",
    "export",
    "loops",
    "normalize",
    "pairs",
    "pileup",
    "plot",
    "score",
    "sim",
    "tads",
    "tiles",
    "validate",
];

/// The ground floor: core types, the formats (`io`) and the tools several rooms share (seeded
/// random streams, cell lists, views), which no room imports another to borrow.
const GROUND: [&str; 8] = [
    "error",
    "genome",
    "geometry",
    "interrupt",
    "io",
    "matrix",
    "numeric",
    "random",
];

/// A module path, e.g. `["io", "hic", "reader"]`.
type Module = Vec<String>;

/// The source files of a crate's module tree: `root` (its `lib.rs` or `main.rs`) and, for each
/// module the tree declares, its file and folder under `dir`, each with its module path. `keep`
/// picks the top-level modules that belong to this tree (the library and the binary share `src/`).
fn tree_files(dir: &Path, root: &str, keep: &dyn Fn(&str) -> bool) -> Vec<(Module, PathBuf)> {
    fn walk(dir: &Path, prefix: &[String], out: &mut Vec<(Module, PathBuf)>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for path in entries {
            let name = path.file_stem().unwrap().to_string_lossy().to_string();
            if path.is_dir() {
                let mut module = prefix.to_vec();
                module.push(name);
                walk(&path, &module, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                if name == "tests" || (prefix.is_empty() && (name == "lib" || name == "main")) {
                    continue;
                }
                let mut module = prefix.to_vec();
                if name != "mod" {
                    module.push(name);
                }
                out.push((module, path));
            }
        }
    }
    let mut files = Vec::new();
    walk(dir, &[], &mut files);
    files.retain(|(module, _)| module.first().is_some_and(|top| keep(top)));
    files.push((Vec::new(), dir.join(root)));
    files
}

/// Every source file of the library under `src/` (the binary's `main.rs` and `cli` excluded), with
/// its module path.
fn library_files() -> Vec<(Module, PathBuf)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    tree_files(&src, "lib.rs", &|top| top != "cli")
}

/// The binary's own sources: `src/main.rs` and the command-line layer `src/cli/`.
fn binary_files() -> Vec<(Module, PathBuf)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    tree_files(&src, "main.rs", &|top| top == "cli")
}

/// The Python binding's sources (`python/src`, its own crate).
fn python_files() -> Vec<(Module, PathBuf)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("python/src");
    tree_files(&src, "lib.rs", &|_| true)
}

/// The source without comments, string literals and `#[cfg(test)]` modules.
fn code_of(text: &str) -> String {
    let mut code = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            match c {
                '\\' => {
                    chars.next();
                }
                '"' => in_string = false,
                _ => {}
            }
            continue;
        }
        match c {
            '/' if chars.peek() == Some(&'/') => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        code.push('\n');
                        break;
                    }
                }
            }
            '"' => in_string = true,
            _ => code.push(c),
        }
    }
    // Test modules: from `#[cfg(test)]` before a `mod` to the end of its braces.
    let mut out = String::with_capacity(code.len());
    let mut rest = code.as_str();
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        // attributes between `#[cfg(test)]` and the `mod` (`#[allow(...)]`) are skipped
        let mut declared = after.trim_start();
        while declared.starts_with("#[") {
            match declared.find(']') {
                Some(end) => declared = declared[end + 1..].trim_start(),
                None => break,
            }
        }
        let declared = declared
            .strip_prefix("pub(crate) ")
            .or_else(|| declared.strip_prefix("pub(super) "))
            .or_else(|| declared.strip_prefix("pub "))
            .unwrap_or(declared);
        if !declared.starts_with("mod ") {
            out.push_str("#[cfg(test)]");
            rest = after;
            continue;
        }
        match after.find(['{', ';']) {
            Some(open) if after.as_bytes()[open] == b'{' => {
                let mut depth = 0usize;
                let mut end = after.len();
                for (i, c) in after[open..].char_indices() {
                    match c {
                        '{' => depth += 1,
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                end = open + i + 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                }
                rest = &after[end..];
            }
            Some(semicolon) => rest = &after[semicolon + 1..],
            None => rest = "",
        }
    }
    out.push_str(rest);
    out
}

/// The paths a source names through `crate::` or `super::` (grouped `use` trees expanded), each
/// as its segments from the crate root.
fn paths_named(code: &str, module: &Module) -> Vec<Vec<String>> {
    let bytes = code.as_bytes();
    let ident_char = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut paths = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts_word = i == 0 || !(ident_char(bytes[i - 1]) || bytes[i - 1] == b':');
        let root = ["crate::", "super::"]
            .into_iter()
            .find(|r| starts_word && code[i..].starts_with(r));
        let Some(root) = root else {
            i += 1;
            continue;
        };
        // `super` is the parent of the file's module.
        let mut base: Vec<String> = if root == "crate::" {
            Vec::new()
        } else {
            let mut base = module.clone();
            base.pop();
            base
        };
        let mut j = i + root.len();
        while code[j..].starts_with("super::") {
            base.pop();
            j += "super::".len();
        }
        let (tree_paths, end) = parse_tree(code, j);
        for mut p in tree_paths {
            let mut full = base.clone();
            full.append(&mut p);
            paths.push(full);
        }
        i = end.max(i + 1);
    }
    paths
}

/// Parse a `use` tree (or an inline path) at `start`: the paths it names and where it ends.
fn parse_tree(code: &str, start: usize) -> (Vec<Vec<String>>, usize) {
    let bytes = code.as_bytes();
    let ident_char = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let mut segments = Vec::new();
    let mut i = start;
    loop {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if i < bytes.len() && bytes[i] == b'{' {
            // Split the group at its top-level commas.
            let mut depth = 0usize;
            let mut item_start = i + 1;
            let mut out = Vec::new();
            let mut k = i;
            while k < bytes.len() {
                match bytes[k] {
                    b'{' => depth += 1,
                    b'}' | b',' if depth == 1 => {
                        let (inner, _) = parse_tree(&code[..k], item_start);
                        for mut p in inner {
                            let mut full = segments.clone();
                            full.append(&mut p);
                            out.push(full);
                        }
                        item_start = k + 1;
                        if bytes[k] == b'}' {
                            return (out, k + 1);
                        }
                    }
                    b'}' => depth -= 1,
                    _ => {}
                }
                k += 1;
            }
            return (out, k);
        }
        let word_start = i;
        while i < bytes.len() && ident_char(bytes[i]) {
            i += 1;
        }
        if i == word_start {
            // a glob (`use super::*`) names everything of the module before it
            if bytes.get(i) == Some(&b'*') {
                segments.push("*".to_string());
                i += 1;
            }
            break;
        }
        let word = &code[word_start..i];
        if word != "self" {
            segments.push(word.to_string());
        }
        if code[i..].starts_with("::") {
            i += 2;
        } else {
            break;
        }
    }
    (vec![segments], i)
}

/// The import graph: module -> modules it names (resolved to modules that have a file).
fn import_graph() -> BTreeMap<Module, BTreeSet<Module>> {
    graph_of(&library_files())
}

/// The import graph of the files of one crate (see [`import_graph`]).
fn graph_of(files: &[(Module, PathBuf)]) -> BTreeMap<Module, BTreeSet<Module>> {
    let modules: BTreeSet<Module> = files.iter().map(|(m, _)| m.clone()).collect();
    let mut graph = BTreeMap::new();
    for (module, path) in files {
        let text = std::fs::read_to_string(path).unwrap();
        let mut targets = BTreeSet::new();
        for named in paths_named(&code_of(&text), module) {
            let resolved = (0..=named.len())
                .rev()
                .map(|n| named[..n].to_vec())
                .find(|prefix| modules.contains(prefix))
                .unwrap_or_default();
            if &resolved != module {
                targets.insert(resolved);
            }
        }
        graph.insert(module.clone(), targets);
    }
    graph
}

/// The cycles among the modules of each folder: an import of `a::x::y` from `a::z` is an edge
/// `a::z -> a::x` between the two children of their common parent `a` (imports between a module
/// and its own descendants or ancestors are how a folder exposes its parts, and are not edges).
fn sibling_cycles(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (from, targets) in graph {
        for to in targets {
            let common = from.iter().zip(to).take_while(|(a, b)| a == b).count();
            if common == from.len() || common == to.len() {
                continue;
            }
            edges
                .entry(from[..=common].to_vec())
                .or_default()
                .insert(to[..=common].to_vec());
        }
    }
    // Tarjan's strongly connected components; every component of two or more is a cycle.
    struct State<'a> {
        edges: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<Module, usize>,
        low: BTreeMap<Module, usize>,
        stack: Vec<Module>,
        on_stack: BTreeSet<Module>,
        components: Vec<Vec<Module>>,
    }
    fn visit(state: &mut State<'_>, v: &Module) {
        let n = state.index.len();
        state.index.insert(v.clone(), n);
        state.low.insert(v.clone(), n);
        state.stack.push(v.clone());
        state.on_stack.insert(v.clone());
        let targets: Vec<Module> = state
            .edges
            .get(v)
            .map(|t| t.iter().cloned().collect())
            .unwrap_or_default();
        for w in &targets {
            if !state.index.contains_key(w) {
                visit(state, w);
                let low = state.low[v].min(state.low[w]);
                state.low.insert(v.clone(), low);
            } else if state.on_stack.contains(w) {
                let low = state.low[v].min(state.index[w]);
                state.low.insert(v.clone(), low);
            }
        }
        if state.low[v] == state.index[v] {
            let mut component = Vec::new();
            while let Some(w) = state.stack.pop() {
                state.on_stack.remove(&w);
                let done = &w == v;
                component.push(w);
                if done {
                    break;
                }
            }
            if component.len() > 1 {
                component.sort();
                state.components.push(component);
            }
        }
    }
    let mut state = State {
        edges: &edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        components: Vec::new(),
    };
    let nodes: Vec<Module> = edges.keys().cloned().collect();
    for v in &nodes {
        if !state.index.contains_key(v) {
            visit(&mut state, v);
        }
    }
    state.components
}

fn name(module: &Module) -> String {
    if module.is_empty() {
        "crate".to_string()
    } else {
        module.join("::")
    }
}

#[test]
fn modules_import_one_another_one_way() {
    let cycles = sibling_cycles(&import_graph());
    let described: Vec<String> = cycles
        .iter()
        .map(|c| c.iter().map(name).collect::<Vec<_>>().join(" <-> "))
        .collect();
    assert!(
        described.is_empty(),
        "import cycles:\n  {}",
        described.join("\n  ")
    );
}

#[test]
fn the_command_line_is_the_binarys() {
    let lib =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs")).unwrap();
    assert!(
        !code_of(&lib).contains("mod cli"),
        "src/lib.rs declares the cli module: the command-line layer belongs to main.rs"
    );
}

/// Every import of an item from an ancestor module's file (its own definitions or its
/// re-exports), as `file: path`: a folder's file exposes its parts, its parts never import it back.
fn imports_from_ancestors(files: &[(Module, PathBuf)]) -> Vec<String> {
    let modules: BTreeSet<Module> = files.iter().map(|(m, _)| m.clone()).collect();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    for (module, path) in files {
        let text = std::fs::read_to_string(path).unwrap();
        for named in ancestor_imports(module, &code_of(&text), &modules) {
            found.push(format!(
                "{}: {}",
                path.strip_prefix(root).unwrap_or(path).display(),
                named.join("::")
            ));
        }
    }
    found.sort();
    found.dedup();
    found
}

/// The paths `code` (of `module`) names that resolve to an ancestor's file (among `modules`,
/// those that have a file) and name something in it.
fn ancestor_imports(module: &Module, code: &str, modules: &BTreeSet<Module>) -> Vec<Vec<String>> {
    paths_named(code, module)
        .into_iter()
        .filter(|named| {
            let resolved = (0..=named.len())
                .rev()
                .map(|n| named[..n].to_vec())
                .find(|prefix| modules.contains(prefix))
                .unwrap_or_default();
            resolved.len() < module.len()
                && module.starts_with(&resolved)
                && named.len() > resolved.len()
        })
        .collect()
}

/// No module imports an item defined in (or re-exported by) an ancestor's file: a folder's
/// file exposes its parts, its parts never import it back (src/cli, src/io and python/src
/// included).
#[test]
fn no_module_imports_from_its_parents_file() {
    let mut found = Vec::new();
    for files in [library_files(), binary_files(), python_files()] {
        found.extend(imports_from_ancestors(&files));
    }
    assert!(
        found.is_empty(),
        "imports of items from an ancestor's file (a folder's file exposes its parts; its parts \
         never import it back: move the item to a module of its own):\n  {}",
        found.join("\n  ")
    );
}

#[test]
fn every_room_is_listed_and_the_ground_floor_imports_no_room() {
    let graph = import_graph();
    let tops: BTreeSet<String> = graph
        .keys()
        .filter(|m| m.len() == 1)
        .map(|m| m[0].clone())
        .collect();
    let unlisted: Vec<&String> = tops
        .iter()
        .filter(|t| !ALGORITHMS.contains(&t.as_str()) && !GROUND.contains(&t.as_str()))
        .collect();
    assert!(
        unlisted.is_empty(),
        "top-level modules in neither ALGORITHMS nor GROUND (tests/architecture.rs): {unlisted:?}"
    );
    let mut offending = Vec::new();
    for (from, targets) in &graph {
        let Some(top) = from.first() else { continue };
        for to in targets {
            let Some(target) = to.first() else { continue };
            let upward = GROUND.contains(&top.as_str()) && ALGORITHMS.contains(&target.as_str());
            // the simulator is a room of its own: no other room borrows its tools
            let borrows_sim = target == "sim" && top != "sim";
            if upward || borrows_sim {
                offending.push(format!("{} imports {}", name(from), name(to)));
            }
        }
    }
    assert!(offending.is_empty(), "{}", offending.join("\n"));
}

/// The checker itself, on sources with a known answer.
#[test]
fn the_checker_sees_grouped_imports_super_and_cycles() {
    let module: Module = vec!["io".into(), "hic".into(), "reader".into()];
    let code = code_of(
        "use crate::{a::{b, c::D}, e};\n// use crate::comment;\nuse super::header::X;\n\
         fn f() { crate::g::h(); let s = \"crate::in_string\"; }\n\
         #[cfg(test)]\nmod tests { use crate::only_in_tests; }\n",
    );
    let mut paths = paths_named(&code, &module);
    paths.sort();
    let expected: Vec<Vec<String>> = vec![
        vec!["a".into(), "b".into()],
        vec!["a".into(), "c".into(), "D".into()],
        vec!["e".into()],
        vec!["g".into(), "h".into()],
        vec!["io".into(), "hic".into(), "header".into(), "X".into()],
    ];
    assert_eq!(paths, expected);

    let m = |s: &str| -> Module { s.split("::").map(String::from).collect() };
    let mut graph = BTreeMap::new();
    graph.insert(m("io::hic::header"), BTreeSet::from([m("io::hic::reader")]));
    graph.insert(m("io::hic::reader"), BTreeSet::from([m("io::hic::norms")]));
    graph.insert(
        m("io::hic::norms"),
        BTreeSet::from([m("io::hic::header"), m("io")]),
    );
    graph.insert(m("io"), BTreeSet::from([m("io::hic::reader")]));
    let cycles = sibling_cycles(&graph);
    assert_eq!(
        cycles,
        vec![vec![
            m("io::hic::header"),
            m("io::hic::norms"),
            m("io::hic::reader")
        ]]
    );
    graph.remove(&m("io::hic::norms"));
    assert!(sibling_cycles(&graph).is_empty());

    // imports from an ancestor's file: its items or a glob over them, not a sibling's, not the
    // ancestor's own children
    let modules = BTreeSet::from([
        m("io"),
        m("io::hic"),
        m("io::hic::reader"),
        m("io::hic::header"),
        Vec::new(),
    ]);
    let code = code_of(
        "use super::{header::H, Helper};\nuse super::*;\nuse crate::io::open;\n\
         use crate::io::hic::header;\nuse crate::Error;\n",
    );
    let found = ancestor_imports(&m("io::hic::reader"), &code, &modules);
    assert_eq!(
        found,
        vec![
            m("io::hic::Helper"),
            m("io::hic::*"),
            m("io::open"),
            vec!["Error".to_string()],
        ]
    );
}

/// The rooms whose work is files (checks and repairs; whole-file outputs that carry computed
/// results): above the algorithms' rule that they never open one.
const FILE_ROOMS: [&str; 2] = ["export", "validate"];

/// The functions of `io` that take a path (`&Path`, `impl AsRef<Path>`, `path: &str`,
/// `uri: &str`): the ways to open a file, read from `io`'s own sources, each with the module
/// that defines it. Free functions by name, associated ones as `Type::name` (a method `fn
/// m(&self, path: &Path)` of a reader already open is not an opener: it is reached through it).
fn io_openers() -> Vec<(Module, String)> {
    let mut openers = Vec::new();
    for (module, path) in library_files() {
        if module.first().map(String::as_str) != Some("io") {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&path).unwrap());
        let mut from = 0;
        while let Some(at) = code[from..].find("pub fn ") {
            let at = from + at;
            let rest = &code[at + "pub fn ".len()..];
            from = at + "pub fn ".len();
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            let Some(open) = rest.find('(') else { break };
            let Some(close) = rest[open..].find(')') else {
                break;
            };
            let params = &rest[open..open + close];
            let takes_path = params.contains("Path")
                || params.contains("path: &str")
                || params.contains("uri: &str");
            if !takes_path || params.contains("self") {
                continue;
            }
            let line_start = code[..at].rfind('\n').map_or(0, |n| n + 1);
            if at == line_start {
                openers.push((module.clone(), name));
                continue;
            }
            // an associated function: the type of the nearest `impl` above it
            let Some(block) = code[..at].rfind("\nimpl") else {
                continue;
            };
            let header = &code[block + 1..];
            let header = &header[..header.find('{').unwrap_or(header.len())];
            let header = header.split(" for ").last().unwrap_or(header);
            let header = header.trim().trim_start_matches("impl").trim();
            let header = header.split('<').next().unwrap_or(header).trim();
            if let Some(ty) = header.split_whitespace().last() {
                openers.push((module.clone(), format!("{ty}::{name}")));
            }
        }
    }
    openers
}

/// The openers of `openers` that `code` (of `module`) reaches: a free function imported or named
/// through `crate::io` (`use crate::io::bed::read_bed`, `crate::io::open_text(`), or called
/// through its module's name (`bed::read_bed(`, `io::open_matrix(`); an associated function
/// called as `Type::name(` with `Type` imported from `io`. And every use of `std::fs` / `File::`.
fn file_calls(code: &str, module: &Module, openers: &[(Module, String)]) -> Vec<String> {
    let mut found = Vec::new();
    for marker in ["std::fs", "File::"] {
        if code.contains(marker) {
            found.push(marker.to_string());
        }
    }
    let io_paths: Vec<Vec<String>> = paths_named(code, module)
        .into_iter()
        .filter(|p| p.first().is_some_and(|top| top == "io"))
        .collect();
    let named = |item: &str| io_paths.iter().any(|p| p.last().is_some_and(|l| l == item));
    for (defined_in, name) in openers {
        let reached = match name.split_once("::") {
            Some((ty, _)) => named(ty) && code.contains(&format!("{name}(")),
            None => {
                let parent = defined_in.last().map_or("io", String::as_str);
                named(name)
                    || code.contains(&format!("{parent}::{name}("))
                    || code.contains(&format!("io::{name}("))
            }
        };
        if reached && !found.contains(name) {
            found.push(name.clone());
        }
    }
    found
}

#[test]
fn no_algorithm_opens_a_file() {
    let openers = io_openers();
    // the check sees the openers it must see
    for name in [
        "open_matrix",
        "open_text",
        "read_bed",
        "read_structure",
        "read_track",
        "Table::read",
    ] {
        assert!(
            openers.iter().any(|(_, n)| n == name),
            "{name} not found among {openers:?}"
        );
    }
    let mut offending = Vec::new();
    for (module, path) in library_files() {
        let Some(top) = module.first() else { continue };
        if !ALGORITHMS.contains(&top.as_str()) || FILE_ROOMS.contains(&top.as_str()) {
            continue;
        }
        let code = code_of(&std::fs::read_to_string(&path).unwrap());
        for call in file_calls(&code, &module, &openers) {
            offending.push(format!(
                "{} ({}) calls {call}",
                name(&module),
                path.display()
            ));
        }
    }
    assert!(
        offending.is_empty(),
        "algorithms take what io read, never a path (the caller reads):\n{}",
        offending.join("\n")
    );
    // and the check fails where it should
    let here: Module = vec!["tads".into(), "insulation".into()];
    let calls = |code: &str| file_calls(code, &here, &openers);
    assert_eq!(calls("use crate::io::bed::read_bed;"), ["read_bed"]);
    assert_eq!(calls("fn f() { crate::io::open_text(p); }"), ["open_text"]);
    assert_eq!(
        calls("use crate::io; fn f() { io::open_matrix(u, o); }"),
        ["open_matrix"]
    );
    assert_eq!(
        calls("use crate::io::tables::{Table, real_text}; fn f() { Table::read(p); }"),
        ["Table::read"]
    );
    assert!(calls("fn describe(r: u8) {} fn f() { describe(1); x.read_bed(2); }").is_empty());
    assert_eq!(
        calls("fn f() { std::fs::File::open(p); }"),
        ["std::fs", "File::"]
    );
}
