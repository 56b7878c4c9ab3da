//! The example refuses bad arguments with a usage error, never a panic.

#[test]
fn locality_refuses_bad_arguments() {
    testkit::check_example_cli("locality", &[&["0"], &["2", "22"], &["nan"]]);
}
