//! The examples refuse bad arguments with a usage error, never a panic.

#[test]
fn city_refuses_bad_arguments() {
    testkit::check_example_cli("city", &[&["0"], &["abc"], &["99999999999"]]);
}

#[test]
fn profile_query_refuses_bad_arguments() {
    testkit::check_example_cli("profile_query", &[&["0"]]);
}

#[cfg(feature = "parallel")]
#[test]
fn query_cpu_refuses_bad_arguments() {
    testkit::check_example_cli("query_cpu", &[&["0"]]);
}
