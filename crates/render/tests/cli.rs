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
        "--gltf",
        "--camera",
        "--mixed-frame",
        "--no-barycentrics",
        "pixel-pull",
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

#[test]
fn gltf_files_render_and_bad_ones_are_refused_by_name() {
    let seeds =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/gltf_import");
    let out = std::env::temp_dir().join(format!("render_cli_gltf_{}", std::process::id()));
    let out_s = out.to_string_lossy().into_owned();
    let file = seeds.join("rich.glb");
    let file_s = file.to_string_lossy().into_owned();
    let (code, stdout, err) = render(&[
        "--gltf", &file_s, "--width", "64", "--height", "48", "--frames", "1", "--out", &out_s,
    ]);
    assert_eq!(code, 0, "{err}");
    for part in [
        "== rich (glTF) ==",
        "meshes 2",
        "instances 3",
        "camera (the file's)",
        "GPU classification == CPU twin",
    ] {
        assert!(stdout.contains(part), "`{part}` in\n{stdout}");
    }
    for image in [
        "rich_deferred.png",
        "rich_baseline.png",
        "rich_debug_vis_ids.png",
    ] {
        assert!(out.join(image).exists(), "{image}");
    }
    let (code, stdout, err) = render(&[
        "--gltf",
        &file_s,
        "--camera",
        "auto",
        "--width",
        "64",
        "--height",
        "48",
        "--frames",
        "1",
        "--no-debug-views",
        "--path",
        "deferred",
        "--out",
        &out_s,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("framing the scene's bounds"), "{stdout}");
    let _ = std::fs::remove_dir_all(&out);

    // A truncated file: the importer's error, naming the file, exit code 1.
    let bytes = std::fs::read(&file).unwrap();
    let cut = std::env::temp_dir().join(format!("render_cli_cut_{}.glb", std::process::id()));
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let (code, _, err) = render(&["--gltf", &cut.to_string_lossy(), "--out", "/nonexistent/x"]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("truncated") && err.contains("render_cli_cut"),
        "{err}"
    );
    let _ = std::fs::remove_file(&cut);
    let (code, _, err) = render(&["--gltf", "/nonexistent/none.glb", "--out", "/nonexistent/x"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("none.glb"), "{err}");
    for (camera, expect) in [
        ("1,2,3", "six numbers"),
        ("0,0,0,0,0,0", "camera.target equals camera.position"),
        ("0,0,0,inf,0,0", "finite"),
        ("near", "not `file`, `auto`"),
    ] {
        let (code, _, err) = render(&["--gltf", "x.glb", "--camera", camera]);
        assert_eq!(code, 2, "{camera}: {err}");
        assert!(err.contains(expect), "{camera}: `{expect}` in\n{err}");
    }
}
