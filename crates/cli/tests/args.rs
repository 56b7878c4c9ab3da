//! The shared pieces against what the binaries' help and the renderer promise: the names
//! on the command line, the limits and messages, and the dusk lighting.

use clap::{Parser, ValueEnum as _};
use cli::{LightPathsArg, LocalLights};
use demo::{DemoOptions, DemoScene};
use gpu::Lighting;
use gpu::config::LightPaths;
use gpu::glam::Vec3;

#[derive(Debug, Parser)]
struct Args {
    #[arg(long, default_value_t = 1, value_parser = cli::image_side())]
    width: u32,
    #[arg(long, default_value_t = 0, value_parser = cli::light_count())]
    lights: u32,
    #[arg(long, default_value_t = 1, value_parser = cli::frame_count())]
    frames: u32,
    #[arg(long, default_value_t = 1.0, value_parser = cli::positive_density, allow_negative_numbers = true)]
    density: f32,
    #[arg(long, value_enum, default_value = "tiled")]
    light_paths: LightPathsArg,
}

fn parse(args: &[&str]) -> Result<Args, String> {
    Args::try_parse_from(std::iter::once("x").chain(args.iter().copied()))
        .map_err(|e| e.to_string())
}

#[test]
fn light_paths_are_named_as_the_help_says() {
    let names: Vec<String> = LightPathsArg::value_variants()
        .iter()
        .filter_map(|v| v.to_possible_value())
        .map(|v| v.get_name().to_owned())
        .collect();
    assert_eq!(names, ["classified", "tiled", "volumes", "every-pixel"]);
    for (name, paths) in [
        ("classified", LightPaths::Classified),
        ("tiled", LightPaths::Tiled),
        ("volumes", LightPaths::Volumes),
        ("every-pixel", LightPaths::EveryPixel),
    ] {
        let a = parse(&["--light-paths", name]).unwrap();
        assert_eq!(a.light_paths.paths(), paths, "{name}");
    }
    assert_eq!(parse(&[]).unwrap().light_paths.paths(), LightPaths::Tiled);
    assert!(
        parse(&["--light-paths", "some"])
            .unwrap_err()
            .contains("--light-paths")
    );
}

#[test]
fn limits_hold_at_both_ends() {
    for (flag, ok, bad) in [
        ("--width", ["1", "16384"], ["0", "16385"]),
        ("--lights", ["0", "4000"], ["-1", "4001"]),
        ("--frames", ["1", "100000"], ["0", "100001"]),
    ] {
        for v in ok {
            assert!(parse(&[&format!("{flag}={v}")]).is_ok(), "{flag} {v}");
        }
        for v in bad {
            let e = parse(&[&format!("{flag}={v}")]).unwrap_err();
            assert!(e.contains(flag), "{flag} {v}: {e}");
        }
    }
    assert_eq!(parse(&["--width", "16384"]).unwrap().width, 16384);
    assert_eq!(parse(&["--lights", "4000"]).unwrap().lights, 4000);
    assert_eq!(parse(&["--frames", "7"]).unwrap().frames, 7);
}

#[test]
fn densities_are_finite_and_above_zero() {
    assert_eq!(parse(&["--density", " 2.5 "]).unwrap().density, 2.5);
    assert_eq!(cli::positive_density("1e-3"), Ok(1e-3));
    for bad in ["0", "-1", "inf", "-inf", "NaN"] {
        let e = cli::positive_density(bad).unwrap_err();
        assert_eq!(e, format!("{bad} is not a finite number above 0"));
        let e = parse(&[&format!("--density={bad}")]).unwrap_err();
        assert!(
            e.contains("--density") && e.contains("finite number above 0"),
            "{e}"
        );
    }
    assert_eq!(
        cli::positive_density("lots").unwrap_err(),
        "`lots` is not a number"
    );
}

#[test]
fn numbers_between_bounds_name_them_and_the_unit() {
    assert_eq!(cli::number_between("0.125", 0.125, 1.0, ""), Ok(0.125));
    assert_eq!(cli::number_between(" 64 ", 0.0, 64.0, " texels"), Ok(64.0));
    for (s, lo, hi, unit, message) in [
        ("0.1", 0.125, 1.0, "", "0.1 is not between 0.125 and 1"),
        (
            "NaN",
            1.0,
            10_000.0,
            " metres",
            "NaN is not between 1 and 10000 metres",
        ),
        (
            "inf",
            0.0,
            64.0,
            " texels",
            "inf is not between 0 and 64 texels",
        ),
        ("far", 1.0, 2.0, "", "`far` is not a number"),
    ] {
        assert_eq!(cli::number_between(s, lo, hi, unit).unwrap_err(), message);
    }
}

#[test]
fn a_density_over_the_limits_names_the_flag_and_the_scene() {
    let options = |density| DemoOptions {
        scene: DemoScene::Forest,
        seed: 1,
        density,
    };
    assert!(cli::check_density(&options(1.0)).is_ok());
    let e = cli::check_density(&options(1e9)).unwrap_err();
    assert!(
        format!("{e:#}").starts_with("--density for the forest scene: "),
        "{e:#}"
    );
}

/// `--no-sun`, `--lights`, the square's half-size and the seed.
fn lights(no_sun: bool, count: u32, half_extent: f32, seed: u64) -> LocalLights {
    LocalLights {
        no_sun,
        count,
        half_extent,
        seed,
    }
}

#[test]
fn no_sun_and_no_lights_leave_the_rest_alone() {
    let day = Lighting::default();
    let target = Vec3::new(5.0, 1.0, -3.0);
    let same = cli::lighting(day.clone(), target, &lights(false, 0, 25.0, 1));
    assert_eq!(same, day);
    let night = cli::lighting(day.clone(), target, &lights(true, 0, 25.0, 1));
    assert_eq!(night.sun_color, Vec3::ZERO);
    assert_eq!(night.ambient, day.ambient);
    assert!(night.point_lights.is_empty() && night.spot_lights.is_empty());
}

#[test]
fn lights_come_at_dusk_around_the_target() {
    let day = Lighting::default();
    let target = Vec3::new(5.0, 1.0, -3.0);
    let dusk = cli::lighting(day.clone(), target, &lights(false, 30, 10.0, 7));
    // Two point lights in three, the rest spots.
    assert_eq!(dusk.point_lights.len(), 20);
    assert_eq!(dusk.spot_lights.len(), 10);
    assert!((dusk.sun_color - day.sun_color * 0.12).abs().max_element() < 1e-6);
    assert!((dusk.ambient - day.ambient * 0.35).abs().max_element() < 1e-6);
    let positions = dusk
        .point_lights
        .iter()
        .map(|l| l.position)
        .chain(dusk.spot_lights.iter().map(|l| l.position));
    for p in positions {
        let d = p - target;
        assert!(
            d.x.abs() <= 10.0 && d.z.abs() <= 10.0,
            "{p} around {target}"
        );
        assert!((0.5..=3.0).contains(&d.y), "{p}: lamps 0.5-3 m up");
    }
    // With the sun off too, it stays off.
    let dark = cli::lighting(day, target, &lights(true, 3, 10.0, 7));
    assert_eq!(dark.sun_color, Vec3::ZERO);
    assert_eq!(dark.point_lights.len() + dark.spot_lights.len(), 3);
}
