//! The import graph between the source files of a tree, and its cycles.
//!
//! Every `.rs` file is read; the crate roots are the files no `mod x;` declaration names. From
//! each root the module tree is built as rustc builds it (`x.rs` or `x/mod.rs` beside a
//! `mod.rs`, `lib.rs`, `main.rs` or root file, `parent/x.rs` beside any other file,
//! `#[path]` attributes, inline modules). A file depends on another when one of its `use`
//! imports, or a path written in its code (`crate::a::B`, `super::c`, `self::d::E`, a child
//! module's `e::F`), names an item defined in the other. Paths are followed through `use`
//! imports and re-exports to the file that defines the item, so a `mod.rs` that only
//! re-exports its children is no stop on the way; a re-export (`pub use`) counts as a
//! dependency only when the file also names the item in its own code. Paths into other
//! crates are left out: cargo already forbids cycles between crates.
//!
//! Two uses are not dependencies (unless `strict`): a file's use of the modules it declares
//! itself, directly or below (a parent wires its parts and may hold what they share: the
//! engine's `mod.rs` builds its parts, which read its `MAX_CHANNELS`), and the uses of test
//! modules (`#[cfg(test)] mod tests`, which may exercise the whole crate). A cycle is then a
//! dependency that comes back through a module the file does not own.
//! A cycle is a strongly connected group of two files or more.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::syntax::{parse, FileSyntax, Import};

/// A dependency of one file on another, with where it is written.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Edge {
    /// The file that names the item (relative to the tree's root).
    pub from: PathBuf,
    /// The file that defines it.
    pub to: PathBuf,
    /// The line in `from`.
    pub line: usize,
    /// The path as written.
    pub path: String,
}

/// A module of a crate.
struct Module {
    file: usize,
    /// The module in that file's syntax.
    local: usize,
    parent: Option<usize>,
    children: BTreeMap<String, usize>,
    /// Compiled for tests only (it or an enclosing module is `#[cfg(test)]`).
    test_only: bool,
}

/// A crate's module tree (module 0 is the root).
struct Crate {
    modules: Vec<Module>,
}

/// Where a path leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Module(usize),
    /// An item of a module.
    Item(usize),
}

/// A file to add to a crate's module tree, and where.
struct FileModule {
    file: usize,
    parent: Option<usize>,
    name: String,
    /// Whether its children sit beside it (`mod.rs`, a crate root, a `#[path]` file) rather
    /// than in a folder named after it.
    mod_rs_like: bool,
    test_only: bool,
}

/// How deep imports are followed (a guard against import loops).
const MAX_DEPTH: usize = 24;

/// The source files of a tree: every `.rs` file outside `target/` and hidden folders, with its
/// syntax.
pub struct Sources {
    /// Paths relative to the root.
    pub files: Vec<PathBuf>,
    syntax: Vec<FileSyntax>,
    index: BTreeMap<PathBuf, usize>,
}

impl Sources {
    /// Reads the `.rs` files under `root`.
    pub fn read(root: &Path) -> Result<Self, String> {
        let mut files = Vec::new();
        super::walk(root, &mut |rel| {
            if rel.extension().is_some_and(|e| e == "rs") {
                files.push(rel.to_path_buf());
            }
        })?;
        files.sort();
        let mut syntax = Vec::with_capacity(files.len());
        for f in &files {
            let path = root.join(f);
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            syntax.push(parse(&text));
        }
        let index = files
            .iter()
            .cloned()
            .enumerate()
            .map(|(i, f)| (f, i))
            .collect();
        Ok(Self {
            files,
            syntax,
            index,
        })
    }

    /// The files a `mod` declaration may name: under `dir`, or its `#[path]`.
    fn candidates(
        &self,
        dir: &Path,
        file: usize,
        decl_path: Option<&str>,
        name: &str,
    ) -> Vec<usize> {
        let paths = match decl_path {
            Some(p) => vec![normalise(
                &self.files[file].parent().unwrap_or(Path::new("")).join(p),
            )],
            None => vec![
                dir.join(format!("{name}.rs")),
                dir.join(name).join("mod.rs"),
            ],
        };
        paths
            .iter()
            .filter_map(|p| self.index.get(p).copied())
            .collect()
    }

    /// The folder holding the children of local module `local` of `file`.
    fn child_dir(&self, file: usize, local: usize, mod_rs_like: bool) -> PathBuf {
        let f = &self.files[file];
        let parent = f.parent().unwrap_or(Path::new("")).to_path_buf();
        let mut dir = if mod_rs_like {
            parent
        } else {
            parent.join(f.file_stem().unwrap_or_default())
        };
        let modules = &self.syntax[file].modules;
        let mut chain = Vec::new();
        let mut m = local;
        while let Some(p) = modules[m].parent {
            chain.push(modules[m].name.clone());
            m = p;
        }
        for name in chain.into_iter().rev() {
            dir.push(name);
        }
        dir
    }

    /// The crate roots: files that no `mod` declaration of another file can name.
    fn roots(&self) -> Vec<usize> {
        let mut claimed = BTreeSet::new();
        for (file, s) in self.syntax.iter().enumerate() {
            for (local, m) in s.modules.iter().enumerate() {
                for decl in &m.file_children {
                    for like in [true, false] {
                        let dir = self.child_dir(file, local, like);
                        claimed.extend(self.candidates(
                            &dir,
                            file,
                            decl.path_attr.as_deref(),
                            &decl.name,
                        ));
                    }
                }
            }
        }
        (0..self.files.len())
            .filter(|f| !claimed.contains(f))
            .collect()
    }

    /// Builds the module tree of the crate rooted at `root`.
    fn build_crate(&self, root: usize) -> Crate {
        let mut c = Crate {
            modules: Vec::new(),
        };
        let top = FileModule {
            file: root,
            parent: None,
            name: String::new(),
            mod_rs_like: true,
            test_only: false,
        };
        self.add_file(&mut c, top, &mut BTreeSet::new());
        c
    }

    /// Adds the modules of a file and, recursively, of the files it declares.
    fn add_file(&self, c: &mut Crate, at: FileModule, seen: &mut BTreeSet<usize>) -> usize {
        let file = at.file;
        seen.insert(file);
        let syntax = &self.syntax[file];
        // Local module → crate module, in order (a local module's parent comes first).
        let mut ids: Vec<usize> = Vec::with_capacity(syntax.modules.len());
        for (local, m) in syntax.modules.iter().enumerate() {
            let id = c.modules.len();
            let (parent, name, test_only) = match m.parent {
                None => (at.parent, at.name.clone(), at.test_only),
                Some(p) => (
                    Some(ids[p]),
                    m.name.clone(),
                    m.test_only || c.modules[ids[p]].test_only,
                ),
            };
            c.modules.push(Module {
                file,
                local,
                parent,
                children: BTreeMap::new(),
                test_only,
            });
            if let Some(p) = parent {
                c.modules[p].children.insert(name, id);
            }
            ids.push(id);
        }
        for (local, m) in syntax.modules.iter().enumerate() {
            let dir = self.child_dir(file, local, at.mod_rs_like);
            for decl in &m.file_children {
                let found = self.candidates(&dir, file, decl.path_attr.as_deref(), &decl.name);
                if let Some(&child) = found.first().filter(|f| !seen.contains(f)) {
                    let mod_rs_like = decl.path_attr.is_some()
                        || self.files[child].file_name().is_some_and(|n| n == "mod.rs");
                    let parent = ids[local];
                    let next = FileModule {
                        file: child,
                        parent: Some(parent),
                        name: decl.name.clone(),
                        mod_rs_like,
                        test_only: decl.test_only || c.modules[parent].test_only,
                    };
                    self.add_file(c, next, seen);
                }
            }
        }
        ids[0]
    }

    fn local(&self, c: &Crate, m: usize) -> &super::syntax::LocalModule {
        &self.syntax[c.modules[m].file].modules[c.modules[m].local]
    }

    /// What `name` means in module `m`: a child module, an item, or an import's target.
    fn lookup(&self, c: &Crate, m: usize, name: &str, depth: usize) -> Option<Target> {
        if depth > MAX_DEPTH {
            return None;
        }
        if let Some(&child) = c.modules[m].children.get(name) {
            return Some(Target::Module(child));
        }
        let local = self.local(c, m);
        if local.items.contains(name) {
            return Some(Target::Item(m));
        }
        if let Some(i) = local
            .imports
            .iter()
            .find(|i| i.name.as_deref() == Some(name))
        {
            return self.resolve(c, m, &i.path, depth + 1);
        }
        local
            .imports
            .iter()
            .filter(|i| i.name.is_none())
            .find_map(|i| match self.resolve(c, m, &i.path, depth + 1)? {
                Target::Module(g) if g != m => self.lookup(c, g, name, depth + 1),
                _ => None,
            })
    }

    /// Where `path`, written in module `m`, leads (`None`: another crate, or unknown).
    fn resolve(&self, c: &Crate, m: usize, path: &[String], depth: usize) -> Option<Target> {
        let (first, rest) = path.split_first()?;
        let mut at = match first.as_str() {
            "crate" => Target::Module(0),
            "self" => Target::Module(m),
            "super" => Target::Module(c.modules[m].parent?),
            name => self.lookup(c, m, name, depth)?,
        };
        for seg in rest {
            let Target::Module(mm) = at else {
                break;
            };
            at = match seg.as_str() {
                "super" => Target::Module(c.modules[mm].parent?),
                "self" => at,
                // A name this tree cannot see (made by a macro): the module's file.
                name => self.lookup(c, mm, name, depth).unwrap_or(Target::Item(mm)),
            };
        }
        Some(at)
    }

    /// The dependencies between files, in file order; with `strict`, also a file's uses of
    /// the modules it declares and the uses of test modules (see the module docs).
    pub fn edges(&self, strict: bool) -> Vec<Edge> {
        let mut edges = BTreeSet::new();
        for root in self.roots() {
            let c = self.build_crate(root);
            for m in 0..c.modules.len() {
                if strict || !c.modules[m].test_only {
                    self.module_edges(&c, m, strict, &mut edges);
                }
            }
        }
        edges.into_iter().collect()
    }

    fn module_edges(&self, c: &Crate, m: usize, strict: bool, edges: &mut BTreeSet<Edge>) {
        let file = c.modules[m].file;
        let local_id = c.modules[m].local;
        let syntax = &self.syntax[file];
        // The module of the whole file: what it declares is its own.
        let mut file_module = m;
        while let Some(p) = c.modules[file_module]
            .parent
            .filter(|&p| c.modules[p].file == file)
        {
            file_module = p;
        }
        let owned = |mut t: usize| loop {
            if t == file_module {
                return true;
            }
            match c.modules[t].parent {
                Some(p) => t = p,
                None => return false,
            }
        };
        let mut add = |target: Option<Target>, line: usize, path: &[String]| {
            let (to, t) = match target {
                Some(Target::Item(t)) => (c.modules[t].file, t),
                _ => return,
            };
            if to != file && (strict || !owned(t)) {
                edges.insert(Edge {
                    from: self.files[file].clone(),
                    to: self.files[to].clone(),
                    line,
                    path: path.join("::"),
                });
            }
        };
        let imports = syntax.modules[local_id].imports.iter().chain(
            syntax
                .block_imports
                .iter()
                .filter(|(l, _)| *l == local_id)
                .map(|(_, i)| i),
        );
        for i in imports {
            if counts(i, syntax) {
                let target = match self.resolve(c, m, &i.path, 0) {
                    // A glob import depends on the module it empties.
                    Some(Target::Module(g)) if i.name.is_none() => Some(Target::Item(g)),
                    t => t,
                };
                add(target, i.line, &i.path);
            }
        }
        for p in syntax.paths.iter().filter(|p| p.module == local_id) {
            add(self.resolve(c, m, &p.path, 0), p.line, &p.path);
        }
    }
}

/// Whether an import is a dependency of its file: always, unless it is a re-export whose name
/// the file does not use itself.
fn counts(i: &Import, syntax: &FileSyntax) -> bool {
    !i.public || i.name.as_ref().is_some_and(|n| syntax.idents.contains(n))
}

/// `a/./b/../c` → `a/c`.
fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in p.components() {
        match part {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The cycles of `edges`: each strongly connected group of two files or more (sorted), with
/// the edges inside it.
pub fn cycles(edges: &[Edge]) -> Vec<(Vec<PathBuf>, Vec<Edge>)> {
    let nodes: BTreeSet<&PathBuf> = edges.iter().flat_map(|e| [&e.from, &e.to]).collect();
    let nodes: Vec<&PathBuf> = nodes.into_iter().collect();
    let id = |p: &PathBuf| nodes.binary_search(&p).expect("a node of the edges");
    let mut next: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); nodes.len()];
    for e in edges {
        next[id(&e.from)].insert(id(&e.to));
    }
    let groups = strongly_connected(&next);
    let mut out = Vec::new();
    for g in groups.into_iter().filter(|g| g.len() > 1) {
        let files: Vec<PathBuf> = g.iter().map(|&n| nodes[n].clone()).collect();
        let inside: Vec<Edge> = edges
            .iter()
            .filter(|e| files.contains(&e.from) && files.contains(&e.to))
            .cloned()
            .collect();
        out.push((files, inside));
    }
    out.sort();
    out
}

/// Tarjan's strongly connected components of a graph given as successor sets (each sorted).
fn strongly_connected(next: &[BTreeSet<usize>]) -> Vec<Vec<usize>> {
    struct State<'a> {
        next: &'a [BTreeSet<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        counter: usize,
        groups: Vec<Vec<usize>>,
    }
    fn visit(s: &mut State<'_>, v: usize) {
        s.index[v] = Some(s.counter);
        s.low[v] = s.counter;
        s.counter += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in s.next[v].iter() {
            match s.index[w] {
                None => {
                    visit(s, w);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(iw) if s.on_stack[w] => s.low[v] = s.low[v].min(iw),
                Some(_) => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut group = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                group.push(w);
                if w == v {
                    break;
                }
            }
            group.sort_unstable();
            s.groups.push(group);
        }
    }
    let n = next.len();
    let mut s = State {
        next,
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: Vec::new(),
        counter: 0,
        groups: Vec::new(),
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(&mut s, v);
        }
    }
    s.groups
}
