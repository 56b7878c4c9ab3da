//! Fuzz body for the `shader` crate's WGSL composer: arbitrary text as the root module
//! (directives, imports of a small fixed library, `enable` lines, anything), composed with
//! an arbitrary feature set. It must return an error or a composition, never panic, the
//! same one twice, and a composition must hold no directive line and every `enable` /
//! `requires` line once, before the first module (that each module comes once, imports
//! first, is the composer's unit tests': fuzzed text may imitate the module headers).

use shader::{Module, compose_source};

/// A fixed library the fuzzed root may import: a chain, a feature-selected import, an
/// `enable`, and a module that imports itself through another (a cycle).
const LIBRARY: &[Module] = &[
    Module::new("t::a", "const T_A: u32 = 1u;\n"),
    Module::new(
        "t::b",
        "#import t::a\n#if x\nenable f16;\n#import t::c\n#else\nconst T_B: u32 = T_A;\n#endif\n",
    ),
    Module::new("t::c", "#if !y\nconst T_C: u32 = 2u;\n#endif\n"),
    Module::new("t::loop1", "#import t::loop2\n"),
    Module::new("t::loop2", "#import t::loop1\n"),
];

const FEATURES: [&str; 4] = ["x", "y", "subgroups", "Bad-Name"];

/// Composes the fuzzed root and checks what comes out.
pub fn shader_compose(data: &[u8]) {
    let (flags, text) = data.split_first().unwrap_or((&0, &[]));
    let features: Vec<&str> = FEATURES
        .iter()
        .enumerate()
        .filter(|(i, _)| flags >> i & 1 == 1)
        .map(|(_, f)| *f)
        .collect();
    let root = String::from_utf8_lossy(text);
    let result = compose_source(&[LIBRARY], "fuzz::root", &root, &features);
    // The same input composes the same way.
    assert_eq!(
        result,
        compose_source(&[LIBRARY], "fuzz::root", &root, &features)
    );
    let out = match result {
        Ok(out) => out,
        Err(e) => {
            // Every error has a message naming where it is.
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    // The hoisted directives, then the modules, each after its `// ---- name ----` line.
    let lines: Vec<&str> = out.lines().collect();
    let first_module = lines
        .iter()
        .position(|l| l.starts_with("// ---- "))
        .expect("the root's own header");
    for line in &lines {
        assert!(
            !line.trim_start().starts_with('#'),
            "a directive survived: {line:?}"
        );
    }
    // Global directives are hoisted above every module, each once.
    let (directives, body) = lines.split_at(first_module);
    for line in body {
        let t = line.trim();
        let global = (t.starts_with("enable ") || t.starts_with("requires ")) && t.ends_with(';');
        assert!(!global, "`{t}` left after the first module");
    }
    for (i, l) in directives.iter().enumerate() {
        assert!(!directives[..i].contains(l), "`{l}` hoisted twice");
    }
}
