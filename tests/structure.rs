//! The files of each folder of `src/` depend one way (ARCHITECTURE.md:
//! "Modules depend downwards, without cycles (between modules, and between
//! the files of a folder)"): within a folder, the graph of which file or
//! subfolder names which is acyclic.
//!
//! A file names another when one of its paths (in a `use`, or in code:
//! `super::avx::group_pulls(…)`) leads into it: directly
//! (`crate::systems::gravity::tree::Octree`, `super::tree::Octree`) or
//! through the folder's re-exports (`crate::systems::StageTimings` names
//! `timings.rs`, whose name `systems/mod.rs` re-exports). Comments and
//! strings are not read; unit tests are, as code of their file. A folder's
//! `mod.rs` (or `lib.rs`) is above all its files, and is not checked.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// The source text with comments, strings and character literals left out
/// (each replaced by a space).
fn strip(src: &str) -> String {
    let c: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    while i < c.len() {
        let at = |k: usize| c.get(k).copied().unwrap_or('\0');
        if c[i] == '/' && at(i + 1) == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if c[i] == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if (c[i] == 'r' || (c[i] == 'b' && at(i + 1) == 'r')) && (i == 0 || !ident(c[i - 1])) && {
            let mut k = i + if c[i] == 'b' { 2 } else { 1 };
            while at(k) == '#' {
                k += 1;
            }
            at(k) == '"'
        } {
            // A raw string: r"…", r#"…"#, br"…".
            i += if c[i] == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while c[i] == '#' {
                hashes += 1;
                i += 1;
            }
            i += 1;
            while i < c.len() && !(c[i] == '"' && (1..=hashes).all(|h| at(i + h) == '#')) {
                i += 1;
            }
            i += 1 + hashes;
            out.push(' ');
        } else if c[i] == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
        } else if c[i] == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            // A character literal ('x', '\n', '\u{…}'), not a lifetime.
            i += 1;
            while i < c.len() && c[i] != '\'' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(' ');
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// Identifiers (keywords too) and punctuation, `::` as one token.
fn tokens(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if c[i].is_whitespace() {
            i += 1;
        } else if c[i].is_alphanumeric() || c[i] == '_' {
            let start = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            out.push(c[start..i].iter().collect());
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            out.push("::".to_owned());
            i += 2;
        } else {
            out.push(c[i].to_string());
            i += 1;
        }
    }
    out
}

/// What one file says: the paths it uses (from the module they are written
/// in, as written), its `pub use` re-exports, and the names it declares
/// public at its top level.
#[derive(Debug, Default)]
struct FileFacts {
    /// (module the path is written in, the path's segments, whether it is
    /// in code for tests only: `#[cfg(test)]`).
    paths: Vec<(Vec<String>, Vec<String>, bool)>,
    /// (the path's segments, the name it is exported as; `*` for a glob).
    reexports: Vec<(Vec<String>, String)>,
    /// Public items declared at the top level.
    items: BTreeSet<String>,
}

/// The paths of a use tree starting at `t[*i]`, each with the name it
/// brings in (`*` for a glob), after `prefix`.
fn use_tree(t: &[String], i: &mut usize, prefix: &[String], out: &mut Vec<(Vec<String>, String)>) {
    let mut path = prefix.to_vec();
    loop {
        match t.get(*i).map(String::as_str) {
            Some("{") => {
                *i += 1;
                loop {
                    if t.get(*i).map(String::as_str) == Some("}") {
                        *i += 1;
                        return;
                    }
                    use_tree(t, i, &path, out);
                    if t.get(*i).map(String::as_str) == Some(",") {
                        *i += 1;
                    }
                    if *i >= t.len() {
                        return;
                    }
                }
            }
            Some("*") => {
                *i += 1;
                out.push((path, "*".to_owned()));
                return;
            }
            Some("::") => *i += 1,
            Some(segment) if segment.chars().all(|ch| ch.is_alphanumeric() || ch == '_') => {
                path.push(segment.to_owned());
                *i += 1;
                if t.get(*i).map(String::as_str) != Some("::") {
                    let mut name = segment.to_owned();
                    if t.get(*i).map(String::as_str) == Some("as") {
                        name = t.get(*i + 1).cloned().unwrap_or_default();
                        *i += 2;
                    }
                    if name == "self" {
                        path.pop();
                        name = path.last().cloned().unwrap_or_default();
                    }
                    out.push((path, name));
                    return;
                }
            }
            _ => return,
        }
    }
}

/// The facts of the file whose module is `module`.
fn facts(src: &str, module: &[String]) -> FileFacts {
    let t = tokens(&strip(src));
    let mut facts = FileFacts::default();
    // Inline modules open (name, the depth of their braces, whether for
    // tests only), the depth.
    let (mut inline, mut depth): (Vec<(String, usize, bool)>, usize) = (Vec::new(), 0);
    // An inline module about to open (its name, whether for tests only),
    // and whether the next item is for tests only.
    let (mut pending_mod, mut cfg_test) = (None, false);
    let here = |inline: &[(String, usize, bool)]| -> Vec<String> {
        module
            .iter()
            .cloned()
            .chain(inline.iter().map(|(n, ..)| n.clone()))
            .collect()
    };
    let in_tests = |inline: &[(String, usize, bool)]| inline.last().is_some_and(|&(.., test)| test);
    let is_pub = |k: usize| {
        // `pub`, `pub(crate)`, `pub(in a::b)` just before token `k`.
        let mut j = k;
        if j > 0 && t[j - 1] == ")" {
            while j > 0 && t[j - 1] != "(" {
                j -= 1;
            }
            j = j.saturating_sub(1);
        }
        j > 0 && t[j - 1] == "pub"
    };
    let mut i = 0;
    while i < t.len() {
        if t[i..].starts_with(&["#", "[", "cfg", "(", "test", ")", "]"].map(str::to_owned)) {
            cfg_test = true;
            i += 7;
            continue;
        }
        match t[i].as_str() {
            "{" => {
                depth += 1;
                if let Some((name, test)) = pending_mod.take() {
                    inline.push((name, depth, test));
                }
            }
            "}" => {
                if inline.last().is_some_and(|&(_, d, _)| d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            "mod" if t.get(i + 2).map(String::as_str) == Some("{") => {
                pending_mod = Some((t[i + 1].clone(), cfg_test || in_tests(&inline)));
            }
            "use" => {
                let public = is_pub(i) && depth == 0;
                let mut k = i + 1;
                let mut trees = Vec::new();
                use_tree(&t, &mut k, &[], &mut trees);
                for (path, name) in trees {
                    if public {
                        facts.reexports.push((path.clone(), name));
                    }
                    facts.paths.push((here(&inline), path, cfg_test || in_tests(&inline)));
                }
                cfg_test = false;
                i = k;
                continue;
            }
            "crate" | "super" | "self" if t.get(i + 1).map(String::as_str) == Some("::") => {
                let mut path = vec![t[i].clone()];
                let mut k = i + 1;
                while t.get(k).map(String::as_str) == Some("::")
                    && t.get(k + 1)
                        .is_some_and(|s| s.chars().all(|ch| ch.is_alphanumeric() || ch == '_'))
                {
                    path.push(t[k + 1].clone());
                    k += 2;
                }
                facts.paths.push((here(&inline), path, in_tests(&inline)));
                i = k;
                continue;
            }
            "struct" | "enum" | "fn" | "static" | "type" | "trait" | "mod" | "union" | "const" if depth == 0 => {
                let (mut start, mut name) = (i, t.get(i + 1).cloned().unwrap_or_default());
                if t[i] == "const" && name == "fn" {
                    name = t.get(i + 2).cloned().unwrap_or_default();
                }
                while start > 0 && matches!(t[start - 1].as_str(), "unsafe" | "const" | "async") {
                    start -= 1;
                }
                if is_pub(start) && name != "_" {
                    facts.items.insert(name);
                }
            }
            _ => {}
        }
        if matches!(
            t[i].as_str(),
            "struct" | "enum" | "fn" | "static" | "type" | "trait" | "mod" | "union" | "const" | "impl"
        ) {
            cfg_test = false;
        }
        i += 1;
    }
    facts
}

/// Every file of the crate, by its module path (`crate`, `crate::systems`,
/// …): its path on disk relative to `src/`, and its text.
type Files = BTreeMap<Vec<String>, (String, String)>;

fn read_src(dir: &Path, relative: &str, files: &mut Files) {
    let mut entries: Vec<_> = fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        let name = path.file_name().unwrap().to_str().unwrap().to_owned();
        let rel = if relative.is_empty() {
            name.clone()
        } else {
            format!("{relative}/{name}")
        };
        if path.is_dir() {
            read_src(&path, &rel, files);
        } else if let Some(stem) = name.strip_suffix(".rs") {
            if rel == "main.rs" {
                continue; // the binary: a crate of its own
            }
            let mut module = vec!["crate".to_owned()];
            module.extend(rel.split('/').map(str::to_owned));
            module.pop();
            if stem != "mod" && rel != "lib.rs" {
                module.push(stem.to_owned());
            }
            files.insert(module, (rel, fs::read_to_string(&path).unwrap()));
        }
    }
}

/// The absolute module path `path` leads to, written in `from`; `None` for
/// another crate's.
fn resolve(from: &[String], path: &[String], files: &Files) -> Option<Vec<String>> {
    let first = path.first()?;
    let mut abs: Vec<String> = match first.as_str() {
        "crate" => vec!["crate".to_owned()],
        "self" => from.to_vec(),
        "super" => from.to_vec(),
        _ => {
            // A bare path: a child module of the file's module (as in a
            // mod.rs's `pub use gravity::…`), or another crate.
            let mut child = from.to_vec();
            child.push(first.clone());
            if !files.contains_key(&child) {
                return None;
            }
            from.to_vec()
        }
    };
    let mut rest = path;
    if first == "crate" || first == "self" {
        rest = &path[1..];
    }
    while rest.first().is_some_and(|s| s == "super") {
        abs.pop();
        rest = &rest[1..];
    }
    abs.extend(rest.iter().cloned());
    Some(abs)
}

/// The names the module `module` exports: its public items and re-exports,
/// globs followed.
fn exported(module: &[String], files: &Files, all: &BTreeMap<Vec<String>, FileFacts>) -> BTreeSet<String> {
    let Some(facts) = all.get(module) else {
        return BTreeSet::new();
    };
    let mut names = facts.items.clone();
    for (path, name) in &facts.reexports {
        if name != "*" {
            names.insert(name.clone());
        } else if let Some(target) = resolve(module, path, files)
            && target.len() > module.len()
        {
            names.extend(exported(&target, files, all));
        }
    }
    names
}

/// For each folder (by its module path), its graph: for each member (a
/// file or a subfolder, by name), the members it names.
type Graphs = BTreeMap<Vec<String>, BTreeMap<String, BTreeSet<String>>>;

/// The graph of every folder of `files`, with the paths in code for tests
/// only or without them.
fn graphs(files: &Files, with_tests: bool) -> Graphs {
    let all: BTreeMap<Vec<String>, FileFacts> = files.iter().map(|(m, (_, src))| (m.clone(), facts(src, m))).collect();
    let folders: Vec<&Vec<String>> = files
        .iter()
        .filter(|(_, (rel, _))| rel == "lib.rs" || rel.ends_with("/mod.rs"))
        .map(|(m, _)| m)
        .collect();
    let mut graphs = Graphs::new();
    for folder in folders {
        let members: BTreeSet<String> = files
            .keys()
            .filter(|m| m.len() == folder.len() + 1 && m.starts_with(folder))
            .map(|m| m[folder.len()].clone())
            .collect();
        // Who owns each name the folder re-exports.
        let mut owners: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (path, name) in &all[folder].reexports {
            let Some(target) = resolve(folder, path, files) else {
                continue;
            };
            if target.len() <= folder.len() || !target.starts_with(folder) {
                continue;
            }
            let owner = target[folder.len()].clone();
            if name == "*" {
                for n in exported(&target, files, &all) {
                    owners.entry(n).or_default().insert(owner.clone());
                }
            } else {
                owners.entry(name.clone()).or_default().insert(owner);
            }
        }
        let graph = graphs.entry(folder.clone()).or_default();
        for (module, facts) in &all {
            if module.len() <= folder.len() || !module.starts_with(folder) {
                continue;
            }
            let member = &module[folder.len()];
            let names = graph.entry(member.clone()).or_default();
            for (from, path, _) in facts.paths.iter().filter(|&&(.., test)| with_tests || !test) {
                let Some(target) = resolve(from, path, files) else {
                    continue;
                };
                if target.len() <= folder.len() || !target.starts_with(folder) {
                    continue;
                }
                let segment = &target[folder.len()];
                let named: BTreeSet<String> = if members.contains(segment) {
                    [segment.clone()].into()
                } else {
                    owners.get(segment).cloned().unwrap_or_default()
                };
                names.extend(named.into_iter().filter(|n| n != member));
            }
        }
    }
    graphs
}

/// The circles in `graph`: each set of members that all reach each other
/// (a strongly connected component of more than one member), in order.
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    let reach = |from: &String| {
        let (mut seen, mut todo) = (BTreeSet::new(), vec![from.clone()]);
        while let Some(node) = todo.pop() {
            for next in graph.get(&node).into_iter().flatten() {
                if seen.insert(next.clone()) {
                    todo.push(next.clone());
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<&String, BTreeSet<String>> = graph.keys().map(|n| (n, reach(n))).collect();
    let mut found: Vec<BTreeSet<String>> = Vec::new();
    for (node, reached) in &reaches {
        let circle: BTreeSet<String> = reached
            .iter()
            .filter(|other| reaches.get(other).is_some_and(|back| back.contains(*node)))
            .cloned()
            .collect();
        if circle.len() > 1 && !found.contains(&circle) {
            found.push(circle);
        }
    }
    found
}

/// The crate's graphs, with its tests or without.
fn crate_graphs(with_tests: bool) -> Graphs {
    let mut files = Files::new();
    read_src(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), "", &mut files);
    graphs(&files, with_tests)
}

fn module(path: &str) -> Vec<String> {
    path.split("::").map(str::to_owned).collect()
}

/// Every circle among the folders' members, as "folder: member, member".
fn all_circles(graphs: &Graphs) -> Vec<String> {
    graphs
        .iter()
        .flat_map(|(folder, graph)| {
            circles(graph).into_iter().map(move |c| {
                let members: Vec<String> = c.into_iter().collect();
                format!("{}: {}", folder.join("::"), members.join(", "))
            })
        })
        .collect()
}

/// Circles known and left for later, each as "folder: member, member":
/// none. A circle that is found fails the test; one written here that is no
/// longer there fails it too, so the list never outlives its circles.
const KNOWN_CIRCLES: &[&str] = &[];

/// The library's code (tests left out: a stage's tests may build the whole
/// schedule) has no circle but the known ones.
#[test]
fn no_folder_of_src_has_an_import_circle() {
    let found = all_circles(&crate_graphs(false));
    let new: Vec<&String> = found.iter().filter(|c| !KNOWN_CIRCLES.contains(&c.as_str())).collect();
    assert!(new.is_empty(), "import circles: {new:#?}");
    let gone: Vec<&&str> = KNOWN_CIRCLES
        .iter()
        .filter(|k| !found.iter().any(|c| c == *k))
        .collect();
    assert!(
        gone.is_empty(),
        "known circles no longer there, to strike off: {gone:?}"
    );
}

/// The module ladders, one for every folder of two members or more
/// (ARCHITECTURE.md, "The module ladder", shows them, and a test holds it
/// to this table): in each folder named, from the top down, every member
/// (a file or a subfolder) names only members below it, unit tests
/// included. The crate's top level first: the command line over the window
/// over the ensembles and benchmarks, over the headless simulation, over
/// its parts, down to what depends on nothing of Kessler's.
const LADDERS: &[(&str, &[&str])] = &[
    (
        "crate",
        &[
            "prelude",
            "cli",
            "ui",
            "ensemble",
            "calibration",
            "bench",
            "simulation",
            "timed_events",
            "scenario",
            "systems",
            "physics",
            "resources",
            "record",
            "output",
            "input",
            "components",
            "memory",
            "maths",
            "execution",
        ],
    ),
    (
        "crate::systems",
        &[
            "response",
            "shatter",
            "sweep",
            "sort",
            "integrate",
            "gravity",
            "pipeline",
        ],
    ),
    (
        "crate::systems::gravity",
        &[
            "kick",
            "walk",
            "tree",
            "local_expansion",
            "kernel",
            "avx512",
            "avx",
            "columns",
            "source",
        ],
    ),
    (
        "crate::ui",
        &[
            "app", "plugins", "overlay", "tools", "measure", "draw", "view", "widgets", "session", "sets",
        ],
    ),
    (
        "crate::bench",
        &[
            "passes",
            "dispatch",
            "outputs",
            "peak_memory",
            "machine",
            "plot",
            "render",
            "threads_plot",
            "crossover",
            "threads",
            "report",
            "measured_run",
            "config",
        ],
    ),
    ("crate::calibration", &["measure", "stored"]),
    (
        "crate::cli",
        &[
            "entry",
            "bench",
            "calibrate",
            "ensemble",
            "pairs",
            "validate",
            "window",
            "headless",
            "args",
            "failure",
        ],
    ),
    ("crate::components", &["body_state", "body"]),
    (
        "crate::ensemble",
        &[
            "aggregate",
            "local_executor",
            "member",
            "preflight",
            "slurm_executor",
            "error",
            "folder",
            "summary",
            "plot",
            "seeds",
            "config",
        ],
    ),
    (
        "crate::execution",
        &[
            "pool",
            "thread_copies",
            "bevy_pool",
            "claims",
            "keep_warm",
            "mode",
            "policy",
            "worker_pool",
            "split",
        ],
    ),
    (
        "crate::input",
        &[
            "execution_options",
            "read_file",
            "spelling",
            "user_files",
            "limits",
            "ron_text",
            "struct_fields",
            "value_checks",
            "error",
        ],
    ),
    ("crate::maths", &["float_order", "functions", "rng"]),
    ("crate::memory", &["allowance", "heap"]),
    (
        "crate::output",
        &["appended", "check", "figure", "message", "atomic", "csv", "png_image"],
    ),
    ("crate::physics", &["fragments", "totals", "aabb"]),
    ("crate::record", &["dump", "state_hash"]),
    (
        "crate::resources",
        &[
            "body_ids",
            "draw_method",
            "memory_budget",
            "settings_patch",
            "settings_by_name",
            "settings",
            "setting_value",
            "collision_detection",
            "fragment_sizes",
            "gravity_method",
            "integrator",
        ],
    ),
    (
        "crate::scenario",
        &[
            "builtin",
            "event_checks",
            "fields",
            "scale",
            "snapshot",
            "listed",
            "load",
            "contents",
            "generators",
            "initial_state",
            "events",
            "format",
            "ron_form",
            "field_checks",
        ],
    ),
    ("crate::simulation", &["headless_run", "timeline", "spawn"]),
    (
        "crate::systems::pipeline",
        &[
            "schedule",
            "stage_clock",
            "fault",
            "timings",
            "update_count",
            "pair_limit",
            "stages",
        ],
    ),
    (
        "crate::systems::response",
        &["time_order", "escaped", "outcomes", "matching", "swept", "contact"],
    ),
    (
        "crate::systems::sort",
        &["sorted_boxes", "repair", "ordering", "filing", "boxes", "grid"],
    ),
    ("crate::timed_events", &["queue", "apply"]),
    (
        "crate::ui::draw",
        &[
            "celestials",
            "instancing",
            "meshes",
            "present_mode",
            "trails",
            "atmosphere",
            "body_colors",
            "instanced_draw",
            "planet_texture",
            "backdrop",
            "instance_slot",
        ],
    ),
    (
        "crate::ui::measure",
        &["film", "capture", "frame_stats", "gpu_memory", "picture", "pipelines"],
    ),
    ("crate::ui::overlay", &["hud", "panel", "cascade"]),
    (
        "crate::ui::overlay::panel",
        &["run", "execution", "physics", "scene", "rendering"],
    ),
    (
        "crate::ui::session",
        &[
            "drive",
            "snapshot_save",
            "output_failures",
            "startup",
            "offscreen",
            "scene",
            "settings_file",
            "update_clock",
            "window_options",
            "sandbox_settings",
        ],
    ),
    ("crate::ui::tools", &["panel_section", "script", "actions", "rewind"]),
    ("crate::ui::view", &["camera", "selection", "main_camera"]),
];

/// The members of `graph` that name one at or above their own rung of
/// `ladder` (top first), as "member names named".
fn up_the_ladder(graph: &BTreeMap<String, BTreeSet<String>>, ladder: &[&str]) -> Vec<String> {
    let mut upward = Vec::new();
    for (k, member) in ladder.iter().enumerate() {
        for named in graph.get(*member).into_iter().flatten() {
            if ladder.iter().position(|m| m == named).is_none_or(|rung| rung <= k) {
                upward.push(format!("{member} names {named}, above it or off the ladder"));
            }
        }
    }
    upward
}

/// Each folder in [`LADDERS`] is a ladder, its unit tests included: the
/// ladder names every member, and no member names one above it.
#[test]
fn the_module_ladders_hold_tests_included() {
    let graphs = crate_graphs(true);
    let mut upward = Vec::new();
    for (folder, ladder) in LADDERS {
        let Some(graph) = graphs.get(&module(folder)) else {
            panic!("{folder} is not a folder of src/");
        };
        let members: BTreeSet<&str> = graph.keys().map(String::as_str).collect();
        assert_eq!(
            members,
            ladder.iter().copied().collect(),
            "the ladder of {folder} names every member, and only those"
        );
        upward.extend(
            up_the_ladder(graph, ladder)
                .into_iter()
                .map(|u| format!("{folder}: {u}")),
        );
    }
    assert!(upward.is_empty(), "imports up a ladder: {upward:#?}");
}

/// A member that names one above it, even only in its unit tests, goes up
/// the ladder; one that names those below does not.
#[test]
fn an_import_up_a_ladder_is_found() {
    let file = |rel: &str, src: &str| (rel.to_owned(), src.to_owned());
    let mut files = Files::new();
    files.insert(module("crate"), file("lib.rs", "mod high; mod mid; mod low;"));
    files.insert(
        module("crate::high"),
        file("high.rs", "use crate::mid::M; use crate::low::L;"),
    );
    files.insert(
        module("crate::mid"),
        file("mid.rs", "pub struct M; fn f() { crate::low::g(); }"),
    );
    files.insert(
        module("crate::low"),
        file(
            "low.rs",
            "pub struct L; pub fn g() {} #[cfg(test)] mod tests { use crate::mid::M; }",
        ),
    );
    let ladder = ["high", "mid", "low"];
    let without_tests = graphs(&files, false);
    assert!(up_the_ladder(&without_tests[&module("crate")], &ladder).is_empty());
    let with_tests = graphs(&files, true);
    assert_eq!(
        up_the_ladder(&with_tests[&module("crate")], &ladder),
        ["low names mid, above it or off the ladder"]
    );
}

/// The graphs are read as written: gravity's ladder, a path in code, a name
/// through a folder's re-exports, a subfolder as one member.
#[test]
fn the_graphs_see_uses_paths_in_code_and_re_exports() {
    let graphs = crate_graphs(false);
    let gravity = &graphs[&module("crate::systems::gravity")];
    for (from, to) in [
        ("kick", "walk"),
        ("walk", "tree"),
        ("tree", "kernel"),
        ("kernel", "avx"),
        ("kernel", "avx512"),
        ("avx", "columns"),
        ("columns", "source"),
    ] {
        assert!(gravity[from].contains(to), "{from} -> {to}: {gravity:?}");
    }
    assert!(gravity["source"].is_empty(), "{gravity:?}");
    let systems = &graphs[&module("crate::systems")];
    assert!(systems["gravity"].contains("pipeline"), "{systems:?}");
    assert!(systems["response"].contains("shatter"), "{systems:?}");
    let pipeline = &graphs[&module("crate::systems::pipeline")];
    assert!(pipeline["stage_clock"].contains("timings"), "{pipeline:?}");
    let root = &graphs[&module("crate")];
    assert!(root["scenario"].contains("systems"), "{root:?}");
    // A unit test names what its file's code does not: seen with tests only.
    let physics = &graphs[&module("crate::physics")];
    assert!(!physics["fragments"].contains("aabb"), "{physics:?}");
    assert!(crate_graphs(true)[&module("crate::physics")]["fragments"].contains("aabb"));
}

/// Files that name each other make a circle, whether by `use`, by a path in
/// code or by a re-exported name; comments and strings name nothing.
#[test]
fn a_circle_is_found() {
    let file = |rel: &str, src: &str| (rel.to_owned(), src.to_owned());
    let mut files = Files::new();
    files.insert(module("crate"), file("lib.rs", "mod a; mod b; mod c; pub use c::*;"));
    files.insert(
        module("crate::a"),
        file("a.rs", "use crate::b::{X, self as bee}; pub struct Y; // super::c::Z"),
    );
    files.insert(
        module("crate::b"),
        file(
            "b.rs",
            "pub struct X; fn f() { let s = \"super::c\"; crate::Z::new(); }",
        ),
    );
    files.insert(
        module("crate::c"),
        file(
            "c.rs",
            "pub struct Z; #[cfg(test)] mod tests { use super::*; use super::super::a::Y; }",
        ),
    );
    let with_tests = graphs(&files, true);
    let root = &with_tests[&module("crate")];
    assert_eq!(root["a"], ["b".to_owned()].into());
    assert_eq!(root["b"], ["c".to_owned()].into());
    assert_eq!(root["c"], ["a".to_owned()].into());
    assert_eq!(circles(root), [["a", "b", "c"].map(str::to_owned).into()]);
    // Without the tests, c names nothing.
    let without_tests = graphs(&files, false);
    let without = &without_tests[&module("crate")];
    assert!(without["c"].is_empty() && circles(without).is_empty(), "{without:?}");
}

/// Stages are named in prose, never numbered ("stage 4"): their order is
/// the stage list's (`systems/pipeline/stages.rs`), and numbers went stale before.
#[test]
fn no_prose_numbers_a_stage() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut texts = Vec::new();
    let mut stack = vec![root.join("src"), root.join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs" || e == "md") {
                texts.push(path);
            }
        }
    }
    texts.extend(["README.md", "ARCHITECTURE.md"].map(|f| root.join(f)));
    let mut found = Vec::new();
    for path in texts {
        let text = fs::read_to_string(&path).unwrap();
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            for (at, _) in lower.match_indices("stage") {
                let rest = lower[at + "stage".len()..].trim_start_matches('s');
                let mut chars = rest.chars();
                if chars.next() == Some(' ') && chars.next().is_some_and(|c| ('1'..='9').contains(&c)) {
                    found.push(format!("{}:{}: {}", path.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(found.is_empty(), "stages numbered in prose:\n{}", found.join("\n"));
}

/// Every folder of two members or more has a ladder: a new folder says its
/// order, rather than growing one by chance.
#[test]
fn every_folder_of_src_has_a_ladder() {
    let graphs = crate_graphs(true);
    let missing: Vec<String> = graphs
        .iter()
        .filter(|(folder, graph)| graph.len() > 1 && !LADDERS.iter().any(|(f, _)| module(f) == **folder))
        .map(|(folder, _)| folder.join("::"))
        .collect();
    assert!(missing.is_empty(), "folders without a ladder in LADDERS: {missing:?}");
}

/// The ladders as ARCHITECTURE.md lists them, a line each: the folder
/// (`crate` is `src/`), then its members from the top down.
fn ladders_as_listed() -> String {
    LADDERS
        .iter()
        .map(|(folder, ladder)| {
            let path = folder.strip_prefix("crate").unwrap_or(folder).replace("::", "/");
            format!("- `src{path}/`: {}\n", ladder.join(" → "))
        })
        .collect()
}

/// ARCHITECTURE.md's list of the ladders is the table's, and its drawing of
/// the crate's ladder names the crate's members in the table's order.
#[test]
fn the_architecture_map_lists_the_ladders_as_the_table_has_them() {
    let map = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md")).unwrap();
    let listed = ladders_as_listed();
    assert!(
        map.contains(&listed),
        "ARCHITECTURE.md's list of the module ladders differs from LADDERS; it should read:\n{listed}"
    );
    let drawing = map
        .split("### The module ladder")
        .nth(1)
        .and_then(|s| s.split("```").nth(1))
        .expect("ARCHITECTURE.md draws the crate's ladder in a code block");
    let drawn: Vec<&str> = drawing.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert_eq!(drawn, LADDERS[0].1, "ARCHITECTURE.md's drawing of the crate's ladder");
}

/// Most lines of code (its unit tests left out) a file of `src/` may hold
/// without saying why at its top.
const LONGEST_FILE: usize = 600;

/// Every file of `src/` longer than [`LONGEST_FILE`] lines of code says why
/// in its module docs (`//! Longer than 600 lines: …`): a file is one
/// concern, and a long one is split unless there is a reason.
#[test]
fn a_long_file_says_why_it_is_long() {
    let mut files = Files::new();
    read_src(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), "", &mut files);
    let said = format!("//! Longer than {LONGEST_FILE} lines:");
    let unexplained: Vec<String> = files
        .values()
        .filter_map(|(rel, src)| {
            let code = src.split("\n#[cfg(test)]").next().unwrap_or(src).lines().count();
            (code > LONGEST_FILE && !src.contains(&said)).then(|| format!("{rel}: {code} lines"))
        })
        .collect();
    assert!(
        unexplained.is_empty(),
        "files over {LONGEST_FILE} lines of code that do not say why: {unexplained:?}"
    );
}
