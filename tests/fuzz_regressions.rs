//! Replays every committed fuzz crash input (`fuzz/regressions/<target>/*`), every seed
//! (`fuzz/seeds/<target>/*`: valid inputs of a target's format), and a few
//! thousand deterministic pseudo-random inputs (`testkit::Rng`) through each fuzz target's
//! body, so the fuzz targets' checks run on stable Rust in every CI run.

use std::path::Path;

#[test]
fn every_target_has_a_fuzz_binary() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/fuzz_targets");
    for (name, _) in fuzzing::TARGETS {
        let file = dir.join(format!("{name}.rs"));
        assert!(
            file.exists(),
            "fuzz target `{name}` has no {}",
            file.display()
        );
    }
}

#[test]
fn committed_crash_inputs_and_seeds_replay_cleanly() {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz");
    let mut replayed = 0;
    for (name, body) in fuzzing::TARGETS {
        for dir in [
            fuzz.join("regressions").join(name),
            fuzz.join("seeds").join(name),
        ] {
            let Ok(entries) = std::fs::read_dir(dir) else {
                continue;
            };
            for entry in entries {
                let path = entry.expect("readable regressions dir").path();
                let data = std::fs::read(&path).expect("readable crash input");
                body(&data);
                replayed += 1;
            }
        }
    }
    eprintln!("replayed {replayed} committed fuzz inputs");
}

#[test]
fn random_inputs_never_panic() {
    for (name, body) in fuzzing::TARGETS {
        let mut rng = testkit::Rng::new(name.len() as u64);
        for len in [
            0usize, 1, 2, 3, 4, 7, 8, 12, 16, 31, 32, 33, 64, 100, 256, 1000,
        ] {
            for _ in 0..128 {
                let data: Vec<u8> = (0..len).map(|_| rng.next_u64() as u8).collect();
                body(&data);
            }
        }
        // Structured extremes: all zeros and all ones.
        body(&[0u8; 512]);
        body(&[0xffu8; 512]);
    }
}
