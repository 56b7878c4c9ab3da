//! WGSL composition: a module names what it imports, in its own text, and the composer
//! resolves those names across the crates' module lists.
//!
//! Directives are whole lines whose first non-blank character is `#`:
//!
//! | line | meaning |
//! | --- | --- |
//! | `#import visbuf::id` | the named module is emitted before this one (once per composition) |
//! | `#if subgroups`, `#if !subgroups` | the lines up to the matching `#else` / `#endif` are kept only if the feature is on (off) |
//! | `#else`, `#endif` | as usual; blocks nest |
//!
//! `#import` lines inside an inactive block are ignored, so a module can pick one of two
//! implementations by feature. `enable ...;` and `requires ...;` lines are hoisted to the
//! top of the output (WGSL wants them before any declaration), each once. Nothing else is
//! rewritten: no name mangling, no text substitution (the workspace prefixes every
//! module-scope name with its crate, `visbuf_pack_id`, `TILING_TILE_SIZE`, so modules
//! concatenate without clashes). Numeric variants are WGSL `override` constants set at
//! pipeline creation, not composer features.

use alloc::collections::BTreeSet;
use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;

/// One WGSL source file of the workspace, by the name other files import it with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Module {
    /// `crate::file`, the file's path under the crate's `src/wgsl/` without `.wgsl` (e.g.
    /// `visbuf::id` is `crates/visbuf/src/wgsl/id.wgsl`).
    pub name: &'static str,
    /// The text, with its directive lines.
    pub source: &'static str,
}

impl Module {
    /// A module named `name` with `source`.
    #[must_use]
    pub const fn new(name: &'static str, source: &'static str) -> Self {
        Self { name, source }
    }

    /// The modules this one imports with `features` on (in order, each once).
    ///
    /// # Errors
    /// A malformed directive ([`Error::Directive`]).
    pub fn imports(&self, features: &[&str]) -> Result<Vec<&'static str>, Error> {
        Ok(parse(self.name, self.source, features)?.imports)
    }
}

/// Why a composition failed. Every variant names the module and, where there is one, the
/// line (1-based) of the problem.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Error {
    /// No module of the library has this name.
    UnknownModule {
        /// The name looked up.
        name: String,
        /// The module whose `#import` named it (`None` for the root).
        imported_by: Option<String>,
    },
    /// The modules import each other in a cycle (the chain, first module repeated last).
    Cycle {
        /// Module names along the cycle.
        chain: Vec<String>,
    },
    /// A line starting with `#` that is not a directive, or a directive in the wrong
    /// place (`#else` or `#endif` without `#if`, an `#if` left open, a bad feature name).
    Directive {
        /// The module.
        module: String,
        /// Its line (1-based).
        line: usize,
        /// What is wrong.
        problem: &'static str,
    },
    /// A feature asked for that no `#if` of the composed modules reads (a typo would
    /// otherwise silently select the other branch).
    UnusedFeature {
        /// The feature.
        feature: String,
        /// The root module.
        root: String,
    },
    /// A feature a pass does not declare (see [`Pass::features`](crate::Pass::features)).
    UndeclaredFeature {
        /// The feature.
        feature: String,
        /// The pass.
        pass: &'static str,
    },
    /// A name a pass description does not have.
    UnknownName {
        /// The pass.
        pass: &'static str,
        /// "group", "binding" or "entry point".
        what: &'static str,
        /// The name asked for.
        name: String,
    },
    /// A bind group was given no resource for a binding of its description.
    MissingResource {
        /// The pass.
        pass: &'static str,
        /// The group.
        group: &'static str,
        /// The binding.
        binding: &'static str,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::UnknownModule {
                name,
                imported_by: Some(by),
            } => write!(
                f,
                "WGSL module `{by}` imports `{name}`, which is in none of the libraries given"
            ),
            Error::UnknownModule {
                name,
                imported_by: None,
            } => write!(f, "no WGSL module named `{name}` in the libraries given"),
            Error::Cycle { chain } => {
                write!(f, "WGSL modules import each other in a cycle: ")?;
                for (i, m) in chain.iter().enumerate() {
                    if i > 0 {
                        write!(f, " -> ")?;
                    }
                    write!(f, "{m}")?;
                }
                Ok(())
            }
            Error::Directive {
                module,
                line,
                problem,
            } => write!(f, "WGSL module `{module}`, line {line}: {problem}"),
            Error::UnusedFeature { feature, root } => write!(
                f,
                "feature `{feature}` is read by no `#if` of `{root}` or its imports (misspelt?)"
            ),
            Error::UndeclaredFeature { feature, pass } => write!(
                f,
                "pass `{pass}` does not declare feature `{feature}` (see its `features`)"
            ),
            Error::UnknownName { pass, what, name } => {
                write!(f, "pass `{pass}` has no {what} named `{name}`")
            }
            Error::MissingResource {
                pass,
                group,
                binding,
            } => write!(
                f,
                "pass `{pass}`: bind group `{group}` was given no resource for binding `{binding}`"
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for Error {}

/// A module's lines under one feature set: its imports and the lines it keeps.
struct Parsed<'s> {
    imports: Vec<&'s str>,
    /// Kept lines, directives removed.
    body: Vec<&'s str>,
    /// Every feature name an `#if` reads, active or not.
    reads: Vec<&'s str>,
}

fn feature_name(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_lowercase() || c == '_')
        && chars.all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

fn parse<'s>(name: &str, source: &'s str, features: &[&str]) -> Result<Parsed<'s>, Error> {
    let err = |line: usize, problem: &'static str| Error::Directive {
        module: name.into(),
        line: line + 1,
        problem,
    };
    // One entry per open `#if`: (this branch is active, an enclosing branch is active,
    // the `#if`'s line).
    let mut stack: Vec<(bool, bool, usize)> = Vec::new();
    let mut out = Parsed {
        imports: Vec::new(),
        body: Vec::new(),
        reads: Vec::new(),
    };
    let active =
        |stack: &[(bool, bool, usize)]| stack.last().is_none_or(|&(a, outer, _)| a && outer);
    for (i, line) in source.lines().enumerate() {
        let t = line.trim();
        let Some(directive) = t.strip_prefix('#') else {
            if active(&stack) {
                out.body.push(line);
            }
            continue;
        };
        let (word, rest) = directive
            .split_once(char::is_whitespace)
            .map_or((directive, ""), |(w, r)| (w, r.trim()));
        match word {
            "import" => {
                if rest.is_empty() || rest.contains(char::is_whitespace) {
                    return Err(err(i, "`#import` takes one module name, `crate::file`"));
                }
                if active(&stack) && !out.imports.contains(&rest) {
                    out.imports.push(rest);
                }
            }
            "if" => {
                let (negated, name) = match rest.strip_prefix('!') {
                    Some(n) => (true, n.trim()),
                    None => (false, rest),
                };
                if !feature_name(name) {
                    return Err(err(
                        i,
                        "`#if` takes one feature name (lowercase, digits, `_`), optionally after `!`",
                    ));
                }
                out.reads.push(name);
                let on = features.contains(&name) != negated;
                let outer = active(&stack);
                stack.push((on, outer, i));
            }
            "else" => {
                if !rest.is_empty() {
                    return Err(err(i, "`#else` takes nothing after it"));
                }
                let Some(top) = stack.last_mut() else {
                    return Err(err(i, "`#else` without `#if`"));
                };
                top.0 = !top.0;
            }
            "endif" => {
                if !rest.is_empty() {
                    return Err(err(i, "`#endif` takes nothing after it"));
                }
                if stack.pop().is_none() {
                    return Err(err(i, "`#endif` without `#if`"));
                }
            }
            _ => {
                return Err(err(
                    i,
                    "unknown directive (there are `#import`, `#if`, `#else`, `#endif`)",
                ));
            }
        }
    }
    if let Some(&(_, _, line)) = stack.last() {
        return Err(err(line, "`#if` without `#endif`"));
    }
    Ok(out)
}

fn find(library: &[&[Module]], name: &str) -> Option<Module> {
    library
        .iter()
        .flat_map(|l| l.iter())
        .find(|m| m.name == name)
        .copied()
}

/// Whether a kept line is a global directive WGSL wants before every declaration.
fn is_global_directive(line: &str) -> bool {
    let t = line.trim();
    (t.starts_with("enable ") || t.starts_with("requires ")) && t.ends_with(';')
}

struct Composer<'a> {
    library: &'a [&'a [Module]],
    features: &'a [&'a str],
    done: Vec<&'a str>,
    stack: Vec<&'a str>,
    directives: Vec<&'a str>,
    body: String,
    reads: BTreeSet<&'a str>,
}

impl<'a> Composer<'a> {
    fn visit(&mut self, name: &'a str, source: &'a str) -> Result<(), Error> {
        if self.done.contains(&name) {
            return Ok(());
        }
        if let Some(at) = self.stack.iter().position(|&m| m == name) {
            let mut chain: Vec<String> = self.stack[at..].iter().map(|&m| m.into()).collect();
            chain.push(name.into());
            return Err(Error::Cycle { chain });
        }
        let parsed = parse(name, source, self.features)?;
        self.reads.extend(parsed.reads.iter().copied());
        self.stack.push(name);
        for &import in &parsed.imports {
            let Some(m) = find(self.library, import) else {
                return Err(Error::UnknownModule {
                    name: import.into(),
                    imported_by: Some(name.into()),
                });
            };
            self.visit(m.name, m.source)?;
        }
        self.stack.pop();
        self.body.push_str("// ---- ");
        self.body.push_str(name);
        self.body.push_str(" ----\n");
        for line in parsed.body {
            if is_global_directive(line) {
                let d = line.trim();
                if !self.directives.contains(&d) {
                    self.directives.push(d);
                }
            } else {
                self.body.push_str(line);
                self.body.push('\n');
            }
        }
        self.done.push(name);
        Ok(())
    }
}

/// Composes the module named `root`: every module it imports (transitively, each once,
/// imports before importers), then `root`, with the `#if` blocks of `features` kept.
/// `library` is the module lists of every crate the composition may reach (e.g.
/// `&[visbuf::wgsl::MODULES, wave::wgsl::MODULES, tiling::wgsl::MODULES]`).
///
/// ```
/// use shader::{Module, compose};
/// const COMMON: Module = Module::new("demo::common", "const DEMO_ONE: u32 = 1u;\n");
/// const PASS: Module = Module::new(
///     "demo::pass",
///     "#import demo::common\n#if twice\nconst DEMO_N: u32 = 2u * DEMO_ONE;\n#else\nconst DEMO_N: u32 = DEMO_ONE;\n#endif\n",
/// );
/// let wgsl = compose(&[&[COMMON, PASS]], "demo::pass", &["twice"])?;
/// assert!(wgsl.find("DEMO_ONE: u32 = 1u").unwrap() < wgsl.find("DEMO_N: u32 = 2u").unwrap());
/// assert!(!wgsl.contains("DEMO_N: u32 = DEMO_ONE"));
/// # Ok::<(), shader::Error>(())
/// ```
///
/// # Errors
/// An unknown module name, an import cycle, a malformed directive, or a feature that no
/// `#if` of the composed modules reads.
pub fn compose(library: &[&[Module]], root: &str, features: &[&str]) -> Result<String, Error> {
    let Some(m) = find(library, root) else {
        return Err(Error::UnknownModule {
            name: root.into(),
            imported_by: None,
        });
    };
    compose_source(library, m.name, m.source, features)
}

/// [`compose`] with a root that is not in `library`: `source`, named `name` in errors.
/// How tests put a kernel in front of a crate's modules.
///
/// # Errors
/// As [`compose`].
pub fn compose_source(
    library: &[&[Module]],
    name: &str,
    source: &str,
    features: &[&str],
) -> Result<String, Error> {
    let mut c = Composer {
        library,
        features,
        done: Vec::new(),
        stack: Vec::new(),
        directives: Vec::new(),
        body: String::new(),
        reads: BTreeSet::new(),
    };
    c.visit(name, source)?;
    if let Some(unused) = features.iter().find(|f| !c.reads.contains(**f)) {
        return Err(Error::UnusedFeature {
            feature: (*unused).into(),
            root: name.into(),
        });
    }
    let mut out = String::new();
    for d in &c.directives {
        out.push_str(d);
        out.push('\n');
    }
    out.push_str(&c.body);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

    const A: Module = Module::new("t::a", "const T_A: u32 = 1u;\n");
    const B: Module = Module::new("t::b", "#import t::a\nconst T_B: u32 = T_A;\n");
    const C: Module = Module::new(
        "t::c",
        "#import t::a\n#import t::b\nenable f16;\nconst T_C: u32 = T_B;\n",
    );

    fn order(s: &str) -> Vec<&str> {
        s.lines()
            .filter_map(|l| l.strip_prefix("// ---- "))
            .map(|l| l.trim_end_matches(" ----"))
            .collect()
    }

    #[test]
    fn imports_come_first_and_once() {
        let s = compose(&[&[C, B, A]], "t::c", &[]).unwrap();
        assert_eq!(order(&s), ["t::a", "t::b", "t::c"]);
        assert_eq!(s.matches("const T_A").count(), 1);
        assert!(s.starts_with("enable f16;\n"), "{s}");
        assert_eq!(s.matches("enable f16;").count(), 1);
    }

    #[test]
    fn libraries_of_several_crates_resolve() {
        let s = compose(&[&[A], &[B], &[C]], "t::c", &[]).unwrap();
        assert_eq!(order(&s), ["t::a", "t::b", "t::c"]);
    }

    #[test]
    fn features_select_lines_and_imports() {
        let m = Module::new(
            "t::m",
            "#if x\n#import t::a\nX\n#if !y\nXNY\n#else\nXY\n#endif\n#else\nNX\n#endif\nALL\n",
        );
        let lib: &[&[Module]] = &[&[A, m]];
        let body = |f: &[&str]| -> Vec<String> {
            let s = compose(lib, "t::m", f).unwrap();
            s.lines()
                .filter(|l| !l.starts_with("//"))
                .map(String::from)
                .collect()
        };
        assert_eq!(body(&[]), ["NX", "ALL"]);
        assert_eq!(body(&["x"]), ["const T_A: u32 = 1u;", "X", "XNY", "ALL"]);
        assert_eq!(
            body(&["x", "y"]),
            ["const T_A: u32 = 1u;", "X", "XY", "ALL"]
        );
        // `y` is read (inside the `x` block) even when `x` is off.
        assert_eq!(body(&["y"]), ["NX", "ALL"]);
    }

    #[test]
    fn errors_name_the_module_and_line() {
        let lib = |m: Module| -> Result<String, Error> { compose(&[&[A, m]], m.name, &[]) };
        let bad = |src: &'static str| lib(Module::new("t::bad", src)).unwrap_err();
        assert_eq!(
            bad("X\n#endif\n"),
            Error::Directive {
                module: "t::bad".into(),
                line: 2,
                problem: "`#endif` without `#if`"
            }
        );
        assert!(matches!(bad("#if x\n"), Error::Directive { line: 1, .. }));
        assert!(matches!(bad("#else\n"), Error::Directive { line: 1, .. }));
        assert!(matches!(
            bad("#define X\n"),
            Error::Directive { line: 1, .. }
        ));
        assert!(matches!(bad("#if X-Y\n#endif\n"), Error::Directive { .. }));
        assert!(matches!(bad("#import\n"), Error::Directive { .. }));
        assert_eq!(
            bad("#import t::nope\n"),
            Error::UnknownModule {
                name: "t::nope".into(),
                imported_by: Some("t::bad".into())
            }
        );
        assert!(matches!(
            compose(&[&[A]], "t::zzz", &[]),
            Err(Error::UnknownModule {
                imported_by: None,
                ..
            })
        ));
        let e = bad("#import t::nope\n");
        assert!(e.to_string().contains("t::bad"), "{e}");
    }

    #[test]
    fn cycles_are_errors() {
        let x = Module::new("t::x", "#import t::y\n");
        let y = Module::new("t::y", "#import t::z\n");
        let z = Module::new("t::z", "#import t::x\n");
        assert_eq!(
            compose(&[&[x, y, z]], "t::x", &[]),
            Err(Error::Cycle {
                chain: ["t::x", "t::y", "t::z", "t::x"].map(String::from).to_vec()
            })
        );
    }

    #[test]
    fn a_feature_nothing_reads_is_an_error() {
        let m = Module::new("t::m", "#if subgroups\nA\n#endif\n");
        assert!(compose(&[&[m]], "t::m", &["subgroups"]).is_ok());
        assert_eq!(
            compose(&[&[m]], "t::m", &["subgroup"]),
            Err(Error::UnusedFeature {
                feature: "subgroup".into(),
                root: "t::m".into()
            })
        );
    }

    #[test]
    fn a_root_outside_the_library_composes() {
        let s = compose_source(&[&[A, B]], "kernel", "#import t::b\nK\n", &[]).unwrap();
        assert_eq!(order(&s), ["t::a", "t::b", "kernel"]);
    }

    #[test]
    fn imports_lists_active_imports() {
        let m = Module::new("t::m", "#import t::a\n#if x\n#import t::b\n#endif\n");
        assert_eq!(m.imports(&[]).unwrap(), ["t::a"]);
        assert_eq!(m.imports(&["x"]).unwrap(), ["t::a", "t::b"]);
    }
}
