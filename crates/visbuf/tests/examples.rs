//! The example refuses bad arguments with a usage error, never a panic.

#[test]
fn growth_refuses_bad_arguments() {
    testkit::check_example_cli("growth", &[&["extra"]]);
}
