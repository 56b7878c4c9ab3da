//! The `render` binary on bad input: every value is refused with a message naming it, before
//! anything is built, and nothing panics (exit code 101 would say it did).

use std::process::Command;

fn render(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_render"))
        .args(args)
        .output()
        .expect("run render");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn help_lists_the_options() {
    let (code, out, _) = render(&["--help"]);
    assert_eq!(code, 0);
    for option in [
        "--scene",
        "--density",
        "--frames",
        "--primitive-id",
        "--width",
        "--instances",
        "--occlusion",
        "--walk",
        "--lights",
        "--light-area",
        "--all-lights",
        "--no-sun",
        "--no-shadows",
        "--no-baked-sun",
        "--no-shadow-cache",
    ] {
        assert!(out.contains(option), "{option} in\n{out}");
    }
}

#[test]
fn bad_values_are_refused_by_name_without_a_panic() {
    for (args, expect) in [
        (&["--density", "inf"][..], "finite number above 0"),
        (&["--density", "NaN"][..], "finite number above 0"),
        (&["--density=-1"][..], "finite number above 0"),
        (&["--density", "0"][..], "finite number above 0"),
        (&["--density", "lots"][..], "not a number"),
        (&["--frames", "0"][..], "--frames"),
        (&["--width", "0"][..], "--width"),
        (&["--height", "100000"][..], "--height"),
        (&["--scene", "town"][..], "--scene"),
        (&["--instances", "10"][..], "--instances"),
        (&["--instances", "many"][..], "--instances"),
        (&["--walk", "99"][..], "--walk"),
        (&["--walk=-1"][..], "--walk"),
        (&["--occlusion", "sometimes"][..], "--occlusion"),
        (&["--lights", "5000"][..], "--lights"),
        (&["--lights=-3"][..], "--lights"),
        (&["--light-area", "0.5"][..], "between 1 and 10000 metres"),
        (&["--light-area", "NaN"][..], "between 1 and 10000 metres"),
        (&["--light-area", "far"][..], "not a number"),
    ] {
        let (code, _, err) = render(args);
        assert_eq!(code, 2, "{args:?}: clap's usage error\n{err}");
        assert!(err.contains(expect), "{args:?}: `{expect}` in\n{err}");
    }
}

#[test]
fn a_read_back_pyramid_with_a_walking_camera_is_refused() {
    let (code, _, err) = render(&[
        "--scene",
        "city",
        "--walk",
        "2",
        "--occlusion",
        "readback",
        "--out",
        "/nonexistent/x",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("still camera"), "{err}");
}

#[test]
fn a_density_over_the_talk_limits_names_the_limit_and_what_fits() {
    let started = std::time::Instant::now();
    let (code, _, err) = render(&[
        "--scene",
        "grass",
        "--density",
        "1e6",
        "--out",
        "/nonexistent/x",
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("256 passes"), "{err}");
    assert!(err.contains("at most density"), "{err}");
    // Refused from counts, before any instance is placed (it used to allocate 13 GB).
    assert!(started.elapsed().as_secs() < 60);
}
