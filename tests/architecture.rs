//! The library's structure, checked on its source (docs/architecture.md):
//!
//! - each module's files form a tree: within a module, the graph "file A
//!   uses an item defined in file B" (through `use`, `super::…`,
//!   `crate::…` and child-module paths; a `pub use` re-export is not an
//!   edge, it is followed to the file that defines the item) has no cycle, the module's own `mod.rs` counting
//!   as one node;
//! - layers only look down (`conic` … `diagnose`);
//! - no public function returns `Result<_, String>`, no public field holds
//!   one, and no public result keeps its warnings as `Vec<String>`;
//! - no message of the library names a command-line flag (advice about the
//!   command line is the CLI's to give);
//! - no file over 700 lines and no function over 80 lines outside test
//!   code (the BLAS/LAPACK shims of `faer_lapack` aside: generated-style
//!   numeric kernels).
//!
//! The first and the last hold for the whole workspace: the library
//! (`src/`), the command line (`cli/src/`) and the Python binding
//! (`python/src/`); the others are the library's rules. Paths are found in
//! code and inside macro calls whose arguments are expressions (`write!`,
//! `format!`, `vec!`, `assert!`, …).
//!
//! Test modules (`#[cfg(test)]`) are left out: a test may reach anywhere.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use syn::visit::Visit;

/// A module path, `["diagnose", "select"]`; the crate root is `[]`.
type ModPath = Vec<String>;

/// One source file: its module and its parsed items (test code removed).
struct File {
    module: ModPath,
    path: PathBuf,
    items: Vec<syn::Item>,
    /// Lines outside test code.
    lines: usize,
}

fn is_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.parse_args::<syn::Meta>()
                .is_ok_and(|m| m.path().is_ident("test"))
    })
}

/// The workspace's source trees: the library, the command line, the
/// Python binding (each its own crate: `crate::` means its own root).
const TREES: [&str; 3] = ["src", "cli/src", "python/src"];

/// Every `.rs` file of the library (`src/`), with its module path.
fn read_sources() -> Vec<File> {
    read_tree(TREES[0])
}

/// Every `.rs` file under `tree` (relative to the workspace), with its
/// module path (a binary's `main.rs` is the module `main`).
fn read_tree(tree: &str) -> Vec<File> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join(tree);
    let mut out = vec![];
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(read_file(&src, p));
            }
        }
    }
    drop_test_files(out)
}

fn read_file(src: &Path, p: PathBuf) -> File {
    let rel = p.strip_prefix(src).unwrap().with_extension("");
    let mut module: ModPath = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if module.last().is_some_and(|m| m == "mod" || m == "lib") {
        module.pop();
    }
    let text = std::fs::read_to_string(&p).unwrap();
    let parsed = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let test_lines: usize = parsed
        .items
        .iter()
        .filter(|i| is_test(item_attrs(i)))
        .map(span_lines)
        .sum();
    let items = parsed
        .items
        .into_iter()
        .filter(|i| !is_test(item_attrs(i)))
        .collect();
    File {
        module,
        path: p,
        items,
        lines: text.lines().count() - test_lines,
    }
}

/// Files that are test modules of their parent (`#[cfg(test)] mod tests;`).
fn drop_test_files(files: Vec<File>) -> Vec<File> {
    let mut tests = BTreeSet::new();
    for f in &files {
        let text = std::fs::read_to_string(&f.path).unwrap();
        let parsed = syn::parse_file(&text).unwrap();
        for i in &parsed.items {
            if let syn::Item::Mod(m) = i
                && m.content.is_none()
                && is_test(&m.attrs)
            {
                let mut p = f.module.clone();
                p.push(m.ident.to_string());
                tests.insert(p);
            }
        }
    }
    files
        .into_iter()
        .filter(|f| !tests.iter().any(|t| f.module.starts_with(t)))
        .collect()
}

fn item_attrs(i: &syn::Item) -> &[syn::Attribute] {
    use syn::Item::*;
    match i {
        Const(x) => &x.attrs,
        Enum(x) => &x.attrs,
        Fn(x) => &x.attrs,
        Impl(x) => &x.attrs,
        Macro(x) => &x.attrs,
        Mod(x) => &x.attrs,
        Static(x) => &x.attrs,
        Struct(x) => &x.attrs,
        Trait(x) => &x.attrs,
        Type(x) => &x.attrs,
        Use(x) => &x.attrs,
        _ => &[],
    }
}

fn span_lines(i: &impl syn::spanned::Spanned) -> usize {
    let s = i.span();
    s.end().line - s.start().line + 1
}

/// The names an item defines at its module's top level.
fn defined_name(i: &syn::Item) -> Option<String> {
    use syn::Item::*;
    Some(match i {
        Const(x) => x.ident.to_string(),
        Enum(x) => x.ident.to_string(),
        Fn(x) => x.sig.ident.to_string(),
        Macro(x) => x.ident.as_ref()?.to_string(),
        Static(x) => x.ident.to_string(),
        Struct(x) => x.ident.to_string(),
        Trait(x) => x.ident.to_string(),
        Type(x) => x.ident.to_string(),
        _ => return None,
    })
}

/// A `use` tree's leaves: (path, name bound, is a glob).
fn use_leaves(prefix: &[String], t: &syn::UseTree, out: &mut Vec<(Vec<String>, String)>) {
    match t {
        syn::UseTree::Path(p) => {
            let mut v = prefix.to_vec();
            v.push(p.ident.to_string());
            use_leaves(&v, &p.tree, out);
        }
        syn::UseTree::Name(n) if n.ident == "self" => {
            out.push((prefix.to_vec(), prefix.last().cloned().unwrap_or_default()))
        }
        syn::UseTree::Name(n) => {
            let mut v = prefix.to_vec();
            v.push(n.ident.to_string());
            out.push((v, n.ident.to_string()));
        }
        syn::UseTree::Rename(r) => {
            let mut v = prefix.to_vec();
            v.push(r.ident.to_string());
            out.push((v, r.rename.to_string()));
        }
        syn::UseTree::Glob(_) => out.push((prefix.to_vec(), "*".into())),
        syn::UseTree::Group(g) => g.items.iter().for_each(|t| use_leaves(prefix, t, out)),
    }
}

/// Every path a file names (in code, not in comments), as segments.
#[derive(Default)]
struct Paths(Vec<Vec<String>>);

impl<'a> Visit<'a> for Paths {
    fn visit_path(&mut self, p: &'a syn::Path) {
        self.0
            .push(p.segments.iter().map(|s| s.ident.to_string()).collect());
        syn::visit::visit_path(self, p);
    }
    fn visit_item_mod(&mut self, m: &'a syn::ItemMod) {
        if !is_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_item_use(&mut self, _: &'a syn::ItemUse) {}
    // `pub(super)` names no item
    fn visit_visibility(&mut self, _: &'a syn::Visibility) {}
    fn visit_macro(&mut self, m: &'a syn::Macro) {
        for e in macro_args(m) {
            <Self as Visit<'_>>::visit_expr(self, &e);
        }
    }
}

/// A macro call's arguments, when they parse as comma-separated
/// expressions (`write!(f, "{}", crate::x::y())`, `vec![…]`,
/// `assert!(…)`); none for a body of another form.
fn macro_args(m: &syn::Macro) -> Vec<syn::Expr> {
    use syn::punctuated::Punctuated;
    m.parse_body_with(Punctuated::<syn::Expr, syn::Token![,]>::parse_terminated)
        .map(|args| args.into_iter().collect())
        .unwrap_or_default()
}

/// What the crate defines and re-exports, by module.
struct Crate {
    modules: BTreeSet<ModPath>,
    defs: HashMap<ModPath, BTreeSet<String>>,
    reexports: HashMap<ModPath, HashMap<String, Vec<String>>>,
}

impl Crate {
    fn new(files: &[File]) -> Self {
        let mut c = Crate {
            modules: files.iter().map(|f| f.module.clone()).collect(),
            defs: HashMap::new(),
            reexports: HashMap::new(),
        };
        for f in files {
            let defs = f.items.iter().filter_map(defined_name).collect();
            c.defs.insert(f.module.clone(), defs);
            for i in &f.items {
                if let syn::Item::Use(u) = i
                    && !matches!(u.vis, syn::Visibility::Inherited)
                {
                    let mut leaves = vec![];
                    use_leaves(&[], &u.tree, &mut leaves);
                    let map = c.reexports.entry(f.module.clone()).or_default();
                    for (path, name) in leaves {
                        map.insert(name, path);
                    }
                }
            }
        }
        c
    }

    /// `path` (as written in module `m`) as a path from the crate root.
    fn absolute(&self, m: &ModPath, path: &[String]) -> Option<Vec<String>> {
        let first = path.first()?;
        match first.as_str() {
            "crate" => Some(path[1..].to_vec()),
            "self" => Some([m.as_slice(), &path[1..]].concat()),
            "super" => {
                let mut base = m.clone();
                let mut rest = path;
                while rest.first().is_some_and(|s| s == "super") {
                    base.pop();
                    rest = &rest[1..];
                }
                Some([base.as_slice(), rest].concat())
            }
            _ => {
                let mut child = m.clone();
                child.push(first.clone());
                self.modules
                    .contains(&child)
                    .then(|| [m.as_slice(), path].concat())
            }
        }
    }

    /// The file (module) that defines the item at the absolute `path`.
    fn owner(&self, path: &[String], depth: usize) -> Option<ModPath> {
        if depth > 16 {
            return None;
        }
        let k = (0..=path.len())
            .rev()
            .find(|&k| self.modules.contains(&path[..k]))?;
        let module = path[..k].to_vec();
        let Some(name) = path.get(k) else {
            return Some(module);
        };
        if self.defs[&module].contains(name) {
            return Some(module);
        }
        match self.reexports.get(&module).and_then(|r| r.get(name)) {
            Some(target) => {
                let abs = self.absolute(&module, target)?;
                self.owner(&abs, depth + 1)
            }
            None => Some(module),
        }
    }
}

/// Per file, the files (modules) it uses, each with a path that shows it.
fn edges(files: &[File], c: &Crate) -> BTreeMap<ModPath, BTreeMap<ModPath, String>> {
    let mut out: BTreeMap<ModPath, BTreeMap<ModPath, String>> = BTreeMap::new();
    for f in files {
        let mut paths = Paths::default();
        let mut uses = vec![];
        for i in &f.items {
            paths.visit_item(i);
            // a re-export is followed to the file that defines the item
            if let syn::Item::Use(u) = i
                && matches!(u.vis, syn::Visibility::Inherited)
            {
                use_leaves(&[], &u.tree, &mut uses);
            }
        }
        let all = uses.into_iter().map(|(p, _)| p).chain(paths.0);
        let e = out.entry(f.module.clone()).or_default();
        for p in all {
            let Some(abs) = c.absolute(&f.module, &p) else {
                continue;
            };
            if let Some(o) = c.owner(&abs, 0)
                && o != f.module
            {
                e.entry(o).or_insert_with(|| p.join("::"));
            }
        }
    }
    out
}

/// Within each module, the cycles among its files (children collapsed to
/// the child of the module they are in).
fn sibling_cycles(files: &[File], c: &Crate) -> Vec<String> {
    let edges = edges(files, c);
    let mut problems = vec![];
    for parent in &c.modules {
        let node = |f: &ModPath| -> Option<ModPath> {
            if f == parent {
                Some(f.clone())
            } else if f.len() > parent.len() && f.starts_with(parent) {
                Some(f[..=parent.len()].to_vec())
            } else {
                None
            }
        };
        let mut g: BTreeMap<ModPath, BTreeMap<ModPath, String>> = BTreeMap::new();
        for (from, tos) in &edges {
            let Some(a) = node(from) else { continue };
            for (to, why) in tos {
                if let Some(b) = node(to)
                    && a != b
                {
                    g.entry(a.clone())
                        .or_default()
                        .entry(b)
                        .or_insert_with(|| format!("{} ({why})", from.join("/")));
                }
            }
        }
        if let Some(cycle) = find_cycle(&g) {
            problems.push(format!(
                "files of `{}` use each other in a circle: {}",
                parent.join("::"),
                cycle.join(" → ")
            ));
        }
    }
    problems
}

/// One cycle of `g`, as "node (edge's witness)" steps, if there is one.
fn find_cycle(g: &BTreeMap<ModPath, BTreeMap<ModPath, String>>) -> Option<Vec<String>> {
    fn dfs(
        v: &ModPath,
        g: &BTreeMap<ModPath, BTreeMap<ModPath, String>>,
        state: &mut HashMap<ModPath, u8>,
        stack: &mut Vec<(ModPath, String)>,
    ) -> Option<Vec<String>> {
        state.insert(v.clone(), 1);
        for (w, why) in g.get(v).into_iter().flatten() {
            stack.push((w.clone(), why.clone()));
            match state.get(w) {
                Some(1) => {
                    // the steps from w's own entry on (its witness is the
                    // edge that reached it, not part of the cycle)
                    let start = stack.iter().position(|(x, _)| x == w).unwrap_or(0);
                    return Some(
                        stack[start + 1..]
                            .iter()
                            .map(|(_, why)| why.clone())
                            .collect(),
                    );
                }
                None => {
                    if let Some(c) = dfs(w, g, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
            stack.pop();
        }
        state.insert(v.clone(), 2);
        None
    }
    let mut state = HashMap::new();
    for v in g.keys() {
        if !state.contains_key(v)
            && let Some(c) = dfs(v, g, &mut state, &mut vec![(v.clone(), String::new())])
        {
            return Some(c);
        }
    }
    None
}

/// The layers, lowest first: a file may use its own layer and those below.
const LAYERS: [&[&str]; 14] = [
    &["faer_lapack", "numfmt", "io", "linalg", "warning"],
    &["conic"],
    &["sdpa"],
    &["urdf"],
    &["moments"],
    &["dynamics"],
    &["data"],
    &["sim"],
    &["effects"],
    &["export"],
    &["identify"],
    &["excite"],
    &["diagnose"],
    &[],
];

fn layer(m: &ModPath) -> Option<usize> {
    let top = m.first()?;
    LAYERS.iter().position(|l| l.contains(&top.as_str()))
}

#[test]
fn the_files_of_each_module_form_a_tree() {
    let mut problems = vec![];
    for tree in TREES {
        let files = read_tree(tree);
        let c = Crate::new(&files);
        let found = sibling_cycles(&files, &c);
        problems.extend(found.into_iter().map(|p| format!("{tree}: {p}")));
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

#[test]
fn layers_only_look_down() {
    let files = read_sources();
    let c = Crate::new(&files);
    let mut problems = vec![];
    for (from, tos) in edges(&files, &c) {
        for (to, why) in tos {
            if let (Some(a), Some(b)) = (layer(&from), layer(&to))
                && b > a
            {
                problems.push(format!(
                    "{} uses {} ({why}), a layer above it",
                    from.join("::"),
                    to.join("::")
                ));
            }
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

/// `Result<_, String>` or `Vec<String>` as written.
fn type_is(t: &syn::Type, outer: &str, last_arg: &str) -> bool {
    let syn::Type::Path(p) = t else { return false };
    let Some(seg) = p.path.segments.last() else {
        return false;
    };
    let syn::PathArguments::AngleBracketed(a) = &seg.arguments else {
        return false;
    };
    let last = a.args.iter().filter_map(|g| match g {
        syn::GenericArgument::Type(t) => Some(t),
        _ => None,
    });
    seg.ident == outer
        && last
            .last()
            .is_some_and(|t| matches!(t, syn::Type::Path(p) if p.path.is_ident(last_arg)))
}

/// A type that holds `Result<_, String>` anywhere inside it.
fn holds_string_result(t: &syn::Type) -> bool {
    #[derive(Default)]
    struct Find(bool);
    impl<'a> Visit<'a> for Find {
        fn visit_type(&mut self, t: &'a syn::Type) {
            self.0 |= type_is(t, "Result", "String");
            syn::visit::visit_type(self, t);
        }
    }
    let mut f = Find::default();
    f.visit_type(t);
    f.0
}

/// Public functions (free and in impls), public struct fields.
#[derive(Default)]
struct Public {
    string_results: Vec<String>,
    string_warnings: Vec<String>,
}

impl<'a> Visit<'a> for Public {
    fn visit_item_mod(&mut self, m: &'a syn::ItemMod) {
        if !is_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_signature(&mut self, s: &'a syn::Signature) {
        if let syn::ReturnType::Type(_, t) = &s.output
            && holds_string_result(t)
        {
            self.string_results.push(format!("fn {}", s.ident));
        }
    }
    fn visit_item_fn(&mut self, f: &'a syn::ItemFn) {
        if matches!(f.vis, syn::Visibility::Public(_)) {
            self.visit_signature(&f.sig);
        }
    }
    fn visit_impl_item_fn(&mut self, f: &'a syn::ImplItemFn) {
        if matches!(f.vis, syn::Visibility::Public(_)) {
            self.visit_signature(&f.sig);
        }
    }
    fn visit_item_struct(&mut self, s: &'a syn::ItemStruct) {
        if !matches!(s.vis, syn::Visibility::Public(_)) {
            return;
        }
        for f in &s.fields {
            if !matches!(f.vis, syn::Visibility::Public(_)) {
                continue;
            }
            let name = f.ident.as_ref().map(|i| i.to_string()).unwrap_or_default();
            if holds_string_result(&f.ty) {
                self.string_results.push(format!("{}.{name}", s.ident));
            }
            if name == "warnings" && type_is(&f.ty, "Vec", "String") {
                self.string_warnings.push(format!("{}.{name}", s.ident));
            }
        }
    }
}

#[test]
fn errors_and_warnings_are_typed_in_the_public_api() {
    let mut problems = vec![];
    for f in read_sources() {
        let mut p = Public::default();
        for i in &f.items {
            p.visit_item(i);
        }
        let at = f.path.display();
        problems.extend(
            p.string_results
                .iter()
                .map(|x| format!("{at}: {x} has Result<_, String>")),
        );
        problems.extend(
            p.string_warnings
                .iter()
                .map(|x| format!("{at}: {x} is a Vec<String>")),
        );
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

/// String literals that name a command-line flag (`--name`).
#[derive(Default)]
struct Flags(Vec<String>);

impl<'a> Visit<'a> for Flags {
    fn visit_item_mod(&mut self, m: &'a syn::ItemMod) {
        if !is_test(&m.attrs) {
            syn::visit::visit_item_mod(self, m);
        }
    }
    fn visit_attribute(&mut self, _: &'a syn::Attribute) {} // doc comments
    fn visit_macro(&mut self, m: &'a syn::Macro) {
        for e in macro_args(m) {
            <Self as Visit<'_>>::visit_expr(self, &e);
        }
    }
    fn visit_lit_str(&mut self, l: &'a syn::LitStr) {
        let v = l.value();
        let flag = v.match_indices("--").any(|(i, _)| {
            let before = v[..i].chars().next_back();
            let after = v[i + 2..].chars().next();
            before.is_none_or(|c| c.is_whitespace() || "(`'\"".contains(c))
                && after.is_some_and(|c| c.is_ascii_lowercase())
        });
        if flag {
            self.0.push(v);
        }
    }
}

#[test]
fn library_messages_name_no_command_line_flag() {
    let mut problems = vec![];
    for f in read_sources() {
        // the crate root's build-configuration error names cargo's flags
        if f.module.is_empty() {
            continue;
        }
        let mut flags = Flags::default();
        for i in &f.items {
            flags.visit_item(i);
        }
        let at = f.path.display();
        problems.extend(flags.0.iter().map(|s| format!("{at}: \"{s}\"")));
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

#[test]
fn files_and_functions_stay_readable() {
    #[derive(Default)]
    struct Long(Vec<(String, usize)>);
    impl<'a> Visit<'a> for Long {
        fn visit_item_mod(&mut self, m: &'a syn::ItemMod) {
            if !is_test(&m.attrs) {
                syn::visit::visit_item_mod(self, m);
            }
        }
        fn visit_item_fn(&mut self, f: &'a syn::ItemFn) {
            self.0.push((f.sig.ident.to_string(), span_lines(f)));
            syn::visit::visit_item_fn(self, f);
        }
        fn visit_impl_item_fn(&mut self, f: &'a syn::ImplItemFn) {
            self.0.push((f.sig.ident.to_string(), span_lines(f)));
            syn::visit::visit_impl_item_fn(self, f);
        }
    }
    let mut problems = vec![];
    for f in TREES.into_iter().flat_map(read_tree) {
        let at = f.path.display();
        if f.lines > 700 {
            problems.push(format!(
                "{at}: {} lines outside tests (at most 700)",
                f.lines
            ));
        }
        if f.module.first().is_some_and(|m| m == "faer_lapack") {
            continue; // the BLAS/LAPACK shims: numeric kernels
        }
        let mut long = Long::default();
        for i in &f.items {
            long.visit_item(i);
        }
        for (name, lines) in long.0.into_iter().filter(|(_, l)| *l > 80) {
            problems.push(format!("{at}: fn {name} has {lines} lines (at most 80)"));
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

/// The checks see what they are meant to: a known circle (half of it in
/// a macro call), a layer violation, flags (one in a macro call) and a
/// `Result<_, String>` written here are found.
#[test]
fn the_checks_find_what_they_look_for() {
    let parse = |s: &str| syn::parse_file(s).unwrap().items;
    let file = |m: &[&str], src: &str| File {
        module: m.iter().map(|s| s.to_string()).collect(),
        path: PathBuf::from(m.join("/")),
        items: parse(src),
        lines: 1,
    };
    let files = [
        file(&["a"], "mod b; mod c; pub use b::B;"),
        file(
            &["a", "b"],
            "pub struct B; fn f() -> super::c::C { todo!() }",
        ),
        // the circle's other half hides in a macro's arguments
        file(
            &["a", "c"],
            r#"pub struct C; fn s() -> String { format!("{}", crate::a::B::NAME) }"#,
        ),
        file(&["conic"], "fn g() { crate::diagnose::run(); }"),
        file(&["diagnose"], "pub fn run() {}"),
    ];
    let c = Crate::new(&files);
    let cycles = sibling_cycles(&files, &c);
    assert_eq!(cycles.len(), 1, "{cycles:?}");
    assert!(cycles[0].contains("`a`"), "{cycles:?}");
    let e = edges(&files, &c);
    assert!(e[&vec!["conic".to_string()]].contains_key(&vec!["diagnose".to_string()]));
    let mut f = Flags::default();
    f.visit_file(
        &syn::parse_file(
            r#"fn m() -> &'static str { "raise it (--max-memory-gib)" }
               fn n(x: f64) -> String { format!("or (--cutoff-hz {x})") }"#,
        )
        .unwrap(),
    );
    assert_eq!(f.0.len(), 2, "{:?}", f.0);
    let mut p = Public::default();
    let src = "pub fn h() -> Result<(), String> { Ok(()) }
               pub struct R { pub warnings: Vec<String>, pub x: Option<Result<f64, String>> }";
    p.visit_file(&syn::parse_file(src).unwrap());
    assert_eq!(p.string_results, ["fn h", "R.x"]);
    assert_eq!(p.string_warnings, ["R.warnings"]);
}
