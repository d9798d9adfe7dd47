//! The crate's layout: imports run downward only and no files import each other.
//!
//! Reads every source file under `src/`, resolves the paths it uses (`use` declarations and
//! inline `crate::`, `super::`, `self::` paths; a folder's `pub use` of its own files is a
//! re-export that resolves to the file that defines the item) to the files that define them,
//! and checks that
//! - the file graph has no cycle (strongly connected components from petgraph);
//! - no file imports a layer above its own: engine <- plot <- growth, the models and the
//!   teaching server `serve` (which only the program imports) <- the
//!   figure registry (`src/figures.rs`), which nothing in the library imports; the program
//!   (`src/main.rs`, `src/cmd/`) sits on top.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;

/// Source text with comments, string and character literals blanked out (newlines kept).
fn strip(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if b[i] == b'\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c == b'r'
            && matches!(b.get(i + 1), Some(b'"') | Some(b'#'))
            && !ident_before(b, i)
        {
            // Raw string r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&b'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&b'"') {
                out.push(c as char);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == b'"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&b'#')) {
                    j += 1 + hashes;
                    break;
                }
                if b[j] == b'\n' {
                    out.push('\n');
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                if i < b.len() && b[i] == b'\n' {
                    out.push('\n');
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == b'\'' {
            // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
            let rest = &src[i..];
            let lit = if rest.starts_with("'\\") {
                rest[1..].find('\'').map(|k| k + 2)
            } else {
                rest[1..]
                    .char_indices()
                    .nth(1)
                    .filter(|&(_, ch)| ch == '\'')
                    .map(|(k, _)| k + 2)
            };
            match lit {
                Some(n) => {
                    out.push_str("' '");
                    i += n;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            let ch = src[i..].chars().next().unwrap_or(' ');
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

fn ident_before(b: &[u8], i: usize) -> bool {
    i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Sym(char),
    Colons,
}

fn tokens(s: &str) -> Vec<Tok> {
    let cs: Vec<char> = s.chars().collect();
    let mut t = Vec::new();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_alphabetic() || c == '_' {
            let st = i;
            while i < cs.len() && (cs[i].is_alphanumeric() || cs[i] == '_') {
                i += 1;
            }
            t.push(Tok::Ident(cs[st..i].iter().collect()));
        } else if c == ':' && cs.get(i + 1) == Some(&':') {
            t.push(Tok::Colons);
            i += 2;
        } else if c.is_whitespace() || c.is_ascii_digit() {
            i += 1;
        } else {
            t.push(Tok::Sym(c));
            i += 1;
        }
    }
    t
}

/// One path a file refers to, relative to the module where it appears.
#[derive(Clone, Debug)]
struct Ref {
    /// The module (inline modules included) where the path appears.
    scope: Vec<String>,
    segs: Vec<String>,
    /// Part of a `pub use`.
    reexport: bool,
    /// The name it is bound to by a `use` (last segment or `as` alias).
    bound: Option<String>,
    glob: bool,
}

/// Expands a use tree starting at `toks[*i]` with the prefix `pre`.
fn use_tree(
    toks: &[Tok],
    i: &mut usize,
    pre: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>, bool)>,
) {
    let mut path = pre;
    loop {
        match toks.get(*i) {
            Some(Tok::Ident(id)) => {
                path.push(id.clone());
                *i += 1;
                if toks.get(*i) == Some(&Tok::Colons) {
                    *i += 1;
                    continue;
                }
                let mut bound = path.last().cloned();
                if toks.get(*i) == Some(&Tok::Ident("as".into())) {
                    if let Some(Tok::Ident(a)) = toks.get(*i + 1) {
                        bound = Some(a.clone());
                    }
                    *i += 2;
                }
                if path.last().map(String::as_str) == Some("self") {
                    path.pop();
                    if bound.as_deref() == Some("self") {
                        bound = path.last().cloned();
                    }
                }
                out.push((path, bound, false));
                return;
            }
            Some(Tok::Sym('*')) => {
                *i += 1;
                out.push((path, None, true));
                return;
            }
            Some(Tok::Sym('{')) => {
                *i += 1;
                loop {
                    match toks.get(*i) {
                        Some(Tok::Sym('}')) => {
                            *i += 1;
                            return;
                        }
                        Some(Tok::Sym(',')) => *i += 1,
                        None => return,
                        _ => use_tree(toks, i, path.clone(), out),
                    }
                }
            }
            _ => return,
        }
    }
}

/// The paths a file refers to.
fn refs(src: &str, module: &[String]) -> Vec<Ref> {
    let toks = tokens(&strip(src));
    let mut out = Vec::new();
    // Inline modules: (name, brace depth inside it).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut pending_mod: Option<String> = None;
    let scope = |inline: &Vec<(String, usize)>| {
        let mut s = module.to_vec();
        s.extend(inline.iter().map(|m| m.0.clone()));
        s
    };
    let mut i = 0;
    while i < toks.len() {
        match &toks[i] {
            Tok::Sym('{') => {
                depth += 1;
                if let Some(m) = pending_mod.take() {
                    inline.push((m, depth));
                }
                i += 1;
            }
            Tok::Sym('}') => {
                if inline.last().is_some_and(|m| m.1 == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
                i += 1;
            }
            Tok::Sym(';') => {
                pending_mod = None;
                i += 1;
            }
            Tok::Ident(k) if k == "mod" => {
                if let Some(Tok::Ident(name)) = toks.get(i + 1) {
                    pending_mod = Some(name.clone());
                }
                i += 2;
            }
            Tok::Ident(k) if k == "use" => {
                // `pub`, `pub(crate)`, `pub(super)` before it make it a re-export.
                let reexport = (i >= 1 && toks[i - 1] == Tok::Ident("pub".into()))
                    || (i >= 4
                        && toks[i - 1] == Tok::Sym(')')
                        && toks[i - 4] == Tok::Ident("pub".into()));
                i += 1;
                if toks.get(i) == Some(&Tok::Colons) {
                    i += 1;
                }
                let mut trees = Vec::new();
                use_tree(&toks, &mut i, Vec::new(), &mut trees);
                for (segs, bound, glob) in trees {
                    out.push(Ref {
                        scope: scope(&inline),
                        segs,
                        reexport,
                        bound,
                        glob,
                    });
                }
            }
            Tok::Ident(k)
                if (k == "crate" || k == "super" || k == "self")
                    && toks.get(i + 1) == Some(&Tok::Colons)
                    && !(i >= 1 && toks[i - 1] == Tok::Colons) =>
            {
                let mut segs = vec![k.clone()];
                let mut j = i + 1;
                while toks.get(j) == Some(&Tok::Colons) {
                    match toks.get(j + 1) {
                        Some(Tok::Ident(s)) => {
                            segs.push(s.clone());
                            j += 2;
                        }
                        _ => break,
                    }
                }
                out.push(Ref {
                    scope: scope(&inline),
                    segs,
                    reexport: false,
                    bound: None,
                    glob: false,
                });
                i = j;
            }
            _ => i += 1,
        }
    }
    out
}

/// A crate's files by module path.
struct Krate {
    files: BTreeMap<Vec<String>, PathBuf>,
    /// Re-exports: (module, bound name) -> absolute target path.
    aliases: HashMap<(Vec<String>, String), Vec<String>>,
}

fn module_of(root: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(root).unwrap();
    let mut segs: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        segs.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        segs.pop();
    }
    segs
}

/// Absolute module path of `r`, or `None` for another crate's path.
fn absolute(k: &Krate, r: &Ref) -> Option<Vec<String>> {
    let mut segs = r.segs.clone();
    let mut base: Vec<String> = match segs.first().map(String::as_str) {
        Some("crate") => {
            segs.remove(0);
            Vec::new()
        }
        Some("self") => {
            segs.remove(0);
            r.scope.clone()
        }
        Some("super") => {
            let mut b = r.scope.clone();
            while segs.first().map(String::as_str) == Some("super") {
                segs.remove(0);
                b.pop();
            }
            b
        }
        Some(first) => {
            // A child module of the current scope (2018 paths), else an external crate.
            let mut child = r.scope.clone();
            child.push(first.to_string());
            if k.files.contains_key(&child) || k.files.keys().any(|m| m.starts_with(&child)) {
                r.scope.clone()
            } else {
                return None;
            }
        }
        None => return None,
    };
    base.extend(segs);
    Some(base)
}

/// The file that defines what `path` names (following re-exports).
fn resolve(k: &Krate, path: &[String], hops: usize) -> Option<PathBuf> {
    if hops > 16 {
        return None;
    }
    for n in (0..=path.len()).rev() {
        if let Some(f) = k.files.get(&path[..n]) {
            if n < path.len()
                && let Some(target) = k.aliases.get(&(path[..n].to_vec(), path[n].clone()))
            {
                let mut t = target.clone();
                t.extend_from_slice(&path[n + 1..]);
                return resolve(k, &t, hops + 1).or_else(|| Some(f.clone()));
            }
            return Some(f.clone());
        }
    }
    None
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rs_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The layer of a library file: engine 0, plot 1, growth, the models and the teaching server
/// (`serve`, which imports growth and ripple) 2, the registry 3.
fn layer(module: &[String]) -> Option<usize> {
    match module.first().map(String::as_str) {
        Some("engine") => Some(0),
        Some("plot") => Some(1),
        Some(
            "growth" | "ripple" | "tile" | "raytrace" | "windripples" | "dunes" | "cursor"
            | "serve",
        ) => Some(2),
        Some("figures") => Some(3),
        _ => None,
    }
}

/// The file graph of one crate: edges (from, to) between files.
fn edges(root: &Path, files: &[PathBuf]) -> (Krate, BTreeSet<(PathBuf, PathBuf)>) {
    let mut k = Krate {
        files: files
            .iter()
            .map(|f| (module_of(root, f), f.clone()))
            .collect(),
        aliases: HashMap::new(),
    };
    let all: Vec<(PathBuf, Vec<String>, Vec<Ref>)> = files
        .iter()
        .map(|f| {
            let m = module_of(root, f);
            let r = refs(&std::fs::read_to_string(f).unwrap(), &m);
            (f.clone(), m, r)
        })
        .collect();
    for (_, _, rs) in &all {
        for r in rs.iter().filter(|r| r.reexport && !r.glob) {
            if let (Some(abs), Some(b)) = (absolute(&k, r), &r.bound) {
                k.aliases.insert((r.scope.clone(), b.clone()), abs);
            }
        }
    }
    let mut e = BTreeSet::new();
    for (f, m, rs) in &all {
        for r in rs {
            let Some(abs) = absolute(&k, r) else { continue };
            // A folder re-exporting its own files is a facade, not an import.
            if r.reexport && abs.starts_with(m) && abs.len() > m.len() {
                continue;
            }
            if let Some(t) = resolve(&k, &abs, 0)
                && &t != f
            {
                e.insert((f.clone(), t));
            }
        }
    }
    (k, e)
}

fn cycles(e: &BTreeSet<(PathBuf, PathBuf)>) -> Vec<Vec<PathBuf>> {
    let mut g = DiGraph::<PathBuf, ()>::new();
    let mut ix = HashMap::new();
    for (a, b) in e {
        for p in [a, b] {
            if !ix.contains_key(p) {
                ix.insert(p.clone(), g.add_node(p.clone()));
            }
        }
        g.add_edge(ix[a], ix[b], ());
    }
    tarjan_scc(&g)
        .into_iter()
        .filter(|c| c.len() > 1)
        .map(|c| {
            let mut v: Vec<PathBuf> = c.into_iter().map(|n| g[n].clone()).collect();
            v.sort();
            v
        })
        .collect()
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The library's files and the program's (`main.rs` and `cmd/`), each a crate of its own.
fn crates() -> (Vec<PathBuf>, Vec<PathBuf>) {
    let root = src();
    let mut files = Vec::new();
    rs_files(&root, &mut files);
    files.sort();
    files.into_iter().partition(|f| {
        let m = module_of(&root, f);
        !(f.ends_with("main.rs") || m.first().map(String::as_str) == Some("cmd"))
    })
}

#[test]
fn no_file_imports_another_that_imports_it_back() {
    let root = src();
    let (lib, bin) = crates();
    for files in [lib, bin] {
        let (_, e) = edges(&root, &files);
        let c = cycles(&e);
        assert!(c.is_empty(), "import cycles between files: {c:#?}");
    }
}

#[test]
fn imports_run_downward_only() {
    let root = src();
    let (lib, _) = crates();
    let (k, e) = edges(&root, &lib);
    let module = |f: &PathBuf| module_of(&root, f);
    let mut bad = Vec::new();
    for (a, b) in &e {
        let (ma, mb) = (module(a), module(b));
        // The teaching server sits beside the models: only the program (`src/cmd/`) uses it.
        let top = |m: &[String]| m.first().cloned().unwrap_or_default();
        if top(&mb) == "serve" && top(&ma) != "serve" {
            bad.push(format!(
                "{} imports {} (only the program may use serve)",
                a.display(),
                b.display()
            ));
        }
        if let (Some(la), Some(lb)) = (layer(&ma), layer(&mb))
            && (lb > la || lb == 3)
        {
            bad.push(format!(
                "{} imports {} (a layer above)",
                a.display(),
                b.display()
            ));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
    // The checker sees the imports it must see: the library has edges into the engine from
    // every model, and none out of it.
    for m in [
        "growth",
        "ripple",
        "tile",
        "raytrace",
        "windripples",
        "dunes",
        "cursor",
        "serve",
        "plot",
    ] {
        assert!(
            e.iter()
                .any(|(a, b)| module(a).first().map(String::as_str) == Some(m)
                    && module(b).first().map(String::as_str) == Some("engine")),
            "no import of the engine found from {m}: the checker lost track of paths"
        );
    }
    assert!(k.files.len() > 60, "only {} files found", k.files.len());
}

#[test]
fn the_checker_finds_a_cycle_and_an_upward_import() {
    // Two files of a made-up crate that import each other, one through a folder's re-export.
    let dir = std::env::temp_dir().join(format!("cellsurf-layout-{}", std::process::id()));
    let m = dir.join("model");
    std::fs::create_dir_all(&m).unwrap();
    std::fs::write(
        m.join("mod.rs"),
        "//! crate::engine is in a comment\npub mod a;\npub mod b;\npub use a::Alpha;\n",
    )
    .unwrap();
    std::fs::write(
        m.join("a.rs"),
        "use super::b::Beta;\npub struct Alpha(Beta);\nconst S: &str = \"crate::model::b\";\n",
    )
    .unwrap();
    std::fs::write(
        m.join("b.rs"),
        "pub struct Beta;\nfn f() { let _ = std::mem::size_of::<crate::model::Alpha>(); }\n",
    )
    .unwrap();
    let mut files = Vec::new();
    rs_files(&dir, &mut files);
    let (_, e) = edges(&dir, &files);
    let c = cycles(&e);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(c.len(), 1, "{e:#?}");
    assert_eq!(
        c[0].iter()
            .map(|p| p.file_name().unwrap().to_str().unwrap())
            .collect::<Vec<_>>(),
        ["a.rs", "b.rs"]
    );
    // The facade's re-export is not an edge, and text in comments and strings is not a path.
    assert_eq!(e.len(), 2, "{e:#?}");
    assert_eq!(layer(&["engine".into()]), Some(0));
    assert_eq!(layer(&["figures".into()]), Some(3));
}
