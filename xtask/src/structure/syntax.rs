//! What the structure check reads from one source file: its modules (the file's own and the
//! inline `mod m { … }` ones), each one's `mod x;` declarations, the names it defines and the
//! `use` imports that name things in it, every other `use` (in function bodies), and every
//! path written in the code (`crate::a::B`, `super::f`, `child::g`, in signatures, bodies,
//! attributes and macro arguments alike).

use std::collections::BTreeSet;

use super::lexer::{tokenize, Spanned, Token};

/// A module of a file: index 0 is the file's own module, the others are inline.
#[derive(Debug, Default, Clone)]
pub struct LocalModule {
    /// The name (empty for the file's own module).
    pub name: String,
    /// The enclosing module in the file (`None` for the file's own).
    pub parent: Option<usize>,
    /// Whether it is compiled for tests only (`#[cfg(test)] mod tests { … }`).
    pub test_only: bool,
    /// Names of the items defined here (functions, types, traits, constants, statics,
    /// macros).
    pub items: BTreeSet<String>,
    /// `mod x;` declarations: modules in files of their own.
    pub file_children: Vec<ModDecl>,
    /// The inline modules declared here, as indices into [`FileSyntax::modules`].
    pub inline_children: Vec<usize>,
    /// The module-level `use` imports (they bring names into the module).
    pub imports: Vec<Import>,
}

/// A `mod name;` declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModDecl {
    /// The module's name.
    pub name: String,
    /// Its `#[path = "…"]` attribute, if any.
    pub path_attr: Option<String>,
    /// Whether it is compiled for tests only (`#[cfg(test)]`).
    pub test_only: bool,
}

/// One leaf of a `use` tree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Import {
    /// The path as written (`crate`, `self`, `super` or a name first).
    pub path: Vec<String>,
    /// The name it brings into scope (`None` for a glob, `_` for `as _`).
    pub name: Option<String>,
    /// Whether it is a re-export (`pub use`, `pub(crate) use`, …).
    pub public: bool,
    /// The line of the `use`.
    pub line: usize,
}

/// A path written in the code (outside `use` statements), with two segments or more.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PathRef {
    /// The local module the path is written in.
    pub module: usize,
    /// The segments.
    pub path: Vec<String>,
    /// Its line.
    pub line: usize,
}

/// Everything the check needs from one file.
#[derive(Debug, Default, Clone)]
pub struct FileSyntax {
    /// The file's modules (index 0: the file's own).
    pub modules: Vec<LocalModule>,
    /// `use` imports inside function bodies and blocks: (local module, import).
    pub block_imports: Vec<(usize, Import)>,
    /// Paths in the code.
    pub paths: Vec<PathRef>,
    /// Every identifier outside `use` statements (a re-exported name that also appears here
    /// is used by the file itself).
    pub idents: BTreeSet<String>,
}

/// Keywords that start an item whose name follows.
const ITEM_KEYWORDS: [&str; 8] = [
    "fn", "struct", "enum", "trait", "type", "const", "static", "union",
];

/// Parses a file's source.
pub fn parse(source: &str) -> FileSyntax {
    let tokens = tokenize(source);
    let mut p = Parser {
        tokens: &tokens,
        i: 0,
        out: FileSyntax {
            modules: vec![LocalModule::default()],
            ..FileSyntax::default()
        },
        owner: vec![0; tokens.len()],
        in_use: vec![false; tokens.len()],
    };
    p.items(0, false);
    p.collect_paths();
    p.out
}

struct Parser<'a> {
    tokens: &'a [Spanned],
    i: usize,
    out: FileSyntax,
    /// The local module each token lies in.
    owner: Vec<usize>,
    /// Whether each token belongs to a `use` statement.
    in_use: Vec<bool>,
}

impl<'a> Parser<'a> {
    fn ident(&self, k: usize) -> Option<&'a str> {
        let tokens: &'a [Spanned] = self.tokens;
        match tokens.get(k).map(|t| &t.token) {
            Some(Token::Ident(s)) => Some(s),
            _ => None,
        }
    }

    fn punct(&self, k: usize, c: char) -> bool {
        self.tokens.get(k).map(|t| &t.token) == Some(&Token::Punct(c))
    }

    /// Moves past the token at `self.i`, recording its module.
    fn bump(&mut self, module: usize) {
        if self.i < self.tokens.len() {
            self.owner[self.i] = module;
        }
        self.i += 1;
    }

    /// Reads the items of `module` until the end of the file or, with `in_braces`, its `}`.
    fn items(&mut self, module: usize, in_braces: bool) {
        let mut public = false;
        let mut path_attr = None;
        let mut test_only = false;
        while self.i < self.tokens.len() {
            let k = self.i;
            if self.punct(k, '}') && in_braces {
                self.bump(module);
                return;
            }
            if self.punct(k, '#') {
                let (path, cfg_test) = self.attribute(module);
                path_attr = path.or(path_attr);
                test_only |= cfg_test;
                continue;
            }
            match self.ident(k) {
                Some("pub") => {
                    self.bump(module);
                    if self.punct(self.i, '(') {
                        self.skip_group(module, '(', ')');
                    }
                    public = true;
                    continue;
                }
                Some("use") => {
                    let line = self.tokens[k].line;
                    for import in self.use_tree(module, public, line) {
                        self.out.modules[module].imports.push(import);
                    }
                }
                Some("mod") if self.ident(k + 1).is_some() => {
                    let name = self.ident(k + 1).unwrap_or_default().to_string();
                    self.bump(module);
                    self.bump(module);
                    if self.punct(self.i, '{') {
                        self.bump(module);
                        let child = self.out.modules.len();
                        self.out.modules.push(LocalModule {
                            name,
                            parent: Some(module),
                            test_only,
                            ..LocalModule::default()
                        });
                        self.out.modules[module].inline_children.push(child);
                        self.items(child, true);
                    } else {
                        self.out.modules[module].file_children.push(ModDecl {
                            name,
                            path_attr: path_attr.take(),
                            test_only,
                        });
                    }
                }
                Some("macro_rules") if self.punct(k + 1, '!') => {
                    if let Some(name) = self.ident(k + 2) {
                        self.out.modules[module].items.insert(name.to_string());
                    }
                    self.bump(module);
                }
                Some(kw) if ITEM_KEYWORDS.contains(&kw) => {
                    let mut n = k + 1;
                    if self.ident(n) == Some("mut") {
                        n += 1;
                    }
                    if let Some(name) = self.ident(n).filter(|s| !ITEM_KEYWORDS.contains(s)) {
                        self.out.modules[module].items.insert(name.to_string());
                    }
                    self.bump(module);
                    continue;
                }
                _ if self.punct(k, '{') => self.block(module),
                _ => self.bump(module),
            }
            public = false;
            path_attr = None;
            test_only = false;
        }
    }

    /// An attribute `#[…]` or `#![…]`: skipped; returns the value of a `path = "…"` one, and
    /// whether it is a `cfg` that needs `test` (`cfg(test)`, `cfg(all(test, …))`).
    fn attribute(&mut self, module: usize) -> (Option<String>, bool) {
        self.bump(module);
        if self.punct(self.i, '!') {
            self.bump(module);
        }
        if !self.punct(self.i, '[') {
            return (None, false);
        }
        let start = self.i;
        self.skip_group(module, '[', ']');
        let inner: Vec<&Token> = self.tokens[start + 1..self.i.saturating_sub(1)]
            .iter()
            .map(|t| &t.token)
            .collect();
        let ident = |t: &Token, name: &str| matches!(t, Token::Ident(s) if s == name);
        match inner.as_slice() {
            [p, Token::Punct('='), Token::Str(path)] if ident(p, "path") => {
                (Some(path.clone()), false)
            }
            [cfg, rest @ ..] if ident(cfg, "cfg") => {
                let test = rest.iter().any(|t| ident(t, "test"))
                    && !rest.iter().any(|t| ident(t, "not") || ident(t, "any"));
                (None, test)
            }
            _ => (None, false),
        }
    }

    /// Skips a balanced group from its `open` to its `close`.
    fn skip_group(&mut self, module: usize, open: char, close: char) {
        let mut depth = 0;
        while self.i < self.tokens.len() {
            if self.punct(self.i, open) {
                depth += 1;
            } else if self.punct(self.i, close) {
                depth -= 1;
                if depth == 0 {
                    self.bump(module);
                    return;
                }
            }
            self.bump(module);
        }
    }

    /// A block (function body, `impl`, type body) from its `{` to its `}`: its `use`
    /// statements import into `module` without defining names there.
    fn block(&mut self, module: usize) {
        let mut depth = 0;
        while self.i < self.tokens.len() {
            let k = self.i;
            if self.punct(k, '{') {
                depth += 1;
            } else if self.punct(k, '}') {
                depth -= 1;
                if depth == 0 {
                    self.bump(module);
                    return;
                }
            } else if self.ident(k) == Some("use") {
                let line = self.tokens[k].line;
                for import in self.use_tree(module, false, line) {
                    self.out.block_imports.push((module, import));
                }
                continue;
            }
            self.bump(module);
        }
    }

    /// A `use` statement from `use` to `;`: its leaves.
    fn use_tree(&mut self, module: usize, public: bool, line: usize) -> Vec<Import> {
        let start = self.i;
        self.bump(module);
        let body_start = self.i;
        while self.i < self.tokens.len() && !self.punct(self.i, ';') {
            self.bump(module);
        }
        let end = self.i;
        self.bump(module);
        for flag in &mut self.in_use[start..self.i.min(self.tokens.len())] {
            *flag = true;
        }
        let mut leaves = Vec::new();
        let body: Vec<&Token> = self.tokens[body_start..end]
            .iter()
            .map(|t| &t.token)
            .collect();
        let mut k = 0;
        tree(&body, &mut k, &mut Vec::new(), &mut leaves);
        leaves
            .into_iter()
            .map(|(path, name)| Import {
                path,
                name,
                public,
                line,
            })
            .collect()
    }

    /// Finds the paths of two segments or more outside `use` statements, and the identifiers.
    fn collect_paths(&mut self) {
        let t = self.tokens;
        let mut k = 0;
        while k < t.len() {
            if self.in_use[k] {
                k += 1;
                continue;
            }
            let Token::Ident(first) = &t[k].token else {
                k += 1;
                continue;
            };
            self.out.idents.insert(first.clone());
            let after_sep = k > 0 && t[k - 1].token == Token::PathSep;
            let mut path = vec![first.clone()];
            let mut e = k + 1;
            while e + 1 < t.len() && t[e].token == Token::PathSep {
                match &t[e + 1].token {
                    Token::Ident(s) => {
                        self.out.idents.insert(s.clone());
                        path.push(s.clone());
                        e += 2;
                    }
                    _ => break,
                }
            }
            if path.len() > 1 && !after_sep {
                self.out.paths.push(PathRef {
                    module: self.owner[k],
                    path,
                    line: t[k].line,
                });
            }
            k = e;
        }
    }
}

/// Reads a use tree at `body[*k]` under `prefix`, appending its leaves (path, name).
fn tree(
    body: &[&Token],
    k: &mut usize,
    prefix: &mut Vec<String>,
    leaves: &mut Vec<(Vec<String>, Option<String>)>,
) {
    let depth = prefix.len();
    // `::a::b` (an extern crate path) is read as `a::b`: it names no module of this crate.
    if body.get(*k) == Some(&&Token::PathSep) {
        *k += 1;
    }
    loop {
        match body.get(*k) {
            Some(Token::Ident(s)) if s != "as" => {
                prefix.push(s.clone());
                *k += 1;
                if body.get(*k) == Some(&&Token::PathSep) {
                    *k += 1;
                    continue;
                }
                let name = if body.get(*k) == Some(&&Token::Ident("as".into())) {
                    *k += 1;
                    match body.get(*k) {
                        Some(Token::Ident(alias)) => {
                            *k += 1;
                            alias.clone()
                        }
                        _ => "_".into(),
                    }
                } else {
                    prefix.last().cloned().unwrap_or_default()
                };
                let mut path = prefix.clone();
                let name = if path.last().is_some_and(|s| s == "self") {
                    path.pop();
                    if name == "self" {
                        path.last().cloned().unwrap_or_default()
                    } else {
                        name
                    }
                } else {
                    name
                };
                leaves.push((path, Some(name)));
                break;
            }
            Some(Token::Punct('*')) => {
                *k += 1;
                leaves.push((prefix.clone(), None));
                break;
            }
            Some(Token::Punct('{')) => {
                *k += 1;
                loop {
                    match body.get(*k) {
                        None => break,
                        Some(Token::Punct('}')) => {
                            *k += 1;
                            break;
                        }
                        Some(Token::Punct(',')) => *k += 1,
                        Some(_) => {
                            let mut inner = prefix.clone();
                            let before = *k;
                            tree(body, k, &mut inner, leaves);
                            if *k == before {
                                *k += 1;
                            }
                        }
                    }
                }
                break;
            }
            _ => break,
        }
    }
    prefix.truncate(depth);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leaves(src: &str) -> Vec<(String, Option<String>, bool)> {
        parse(src).modules[0]
            .imports
            .iter()
            .map(|i| (i.path.join("::"), i.name.clone(), i.public))
            .collect()
    }

    #[test]
    fn use_trees_give_each_leaf_its_path_and_name() {
        let got = leaves(
            "use crate::a::{b, c::{d as e, self}, f::*};\npub(crate) use super::g;\nuse h as _;",
        );
        let want = [
            ("crate::a::b", Some("b"), false),
            ("crate::a::c::d", Some("e"), false),
            ("crate::a::c", Some("c"), false),
            ("crate::a::f", None, false),
            ("super::g", Some("g"), true),
            ("h", Some("_"), false),
        ];
        let want: Vec<(String, Option<String>, bool)> = want
            .iter()
            .map(|(p, n, b)| (p.to_string(), n.map(str::to_string), *b))
            .collect();
        assert_eq!(got, want);
    }

    #[test]
    fn items_modules_block_uses_and_paths_are_found() {
        let src = r#"
            #[path = "x/y.rs"]
            mod y;
            pub mod z;
            pub const fn f() -> u8 { use crate::q::R; crate::s::t(); 1 }
            static mut COUNT: u8 = 0;
            #[cfg(test)]
            mod tests { use super::*; fn g() { super::f(); } }
            impl crate::k::K { fn inner() {} }
        "#;
        let s = parse(src);
        let top = &s.modules[0];
        assert_eq!(
            top.file_children,
            [
                ModDecl {
                    name: "y".into(),
                    path_attr: Some("x/y.rs".into()),
                    test_only: false
                },
                ModDecl {
                    name: "z".into(),
                    path_attr: None,
                    test_only: false
                }
            ]
        );
        let items: Vec<&str> = top.items.iter().map(String::as_str).collect();
        assert_eq!(items, ["COUNT", "f"]);
        assert_eq!(s.modules[1].name, "tests");
        assert!(s.modules[1].test_only && !s.modules[0].test_only);
        assert_eq!(s.modules[1].items.iter().collect::<Vec<_>>(), ["g"]);
        assert_eq!(s.block_imports.len(), 1);
        assert_eq!(s.block_imports[0].1.path, ["crate", "q", "R"]);
        let paths: Vec<(usize, String)> = s
            .paths
            .iter()
            .map(|p| (p.module, p.path.join("::")))
            .collect();
        assert_eq!(
            paths,
            [
                (0, "crate::s::t".to_string()),
                (1, "super::f".to_string()),
                (0, "crate::k::K".to_string())
            ]
        );
    }
}
