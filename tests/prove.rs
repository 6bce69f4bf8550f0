//! `shadelab prove`: proof.json against its schema (with teeth), the bounds above the found
//! values, the methods out of reach listed, the found input replayed by `stress --replay`, and
//! the exact error texts of bad input.
use crate::support::*;

#[test]
fn prove_writes_a_valid_proof_whose_found_inputs_replay() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (code, stdout, stderr) = run(&[
        "prove",
        "--methods",
        "newton_raphson,mikami_const,slerp",
        "--max-angle",
        "40",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("newton_raphson"), "{stdout}");
    assert!(stderr.contains("prove: newton_raphson"), "{stderr}");
    let report = read_json(out.join("proof.json"));
    assert_schema(
        &report,
        "docs/proof.schema.json",
        "/methods/0/colour",
        "proven_upper",
    );
    let methods = report["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 2);
    for m in methods {
        for x in m["metrics"].as_array().unwrap() {
            let (p, f) = (
                x["proven_upper"].as_f64().unwrap(),
                x["found"].as_f64().unwrap(),
            );
            assert!(f <= p + 1e-12, "{x}");
        }
        let c = &m["colour"];
        assert!(c["found"].as_f64().unwrap() <= c["proven_upper"].as_f64().unwrap());
    }
    let oor = report["out_of_reach"].as_array().unwrap();
    assert_eq!(oor.len(), 1);
    assert_eq!(oor[0]["name"], "slerp");
    let claims = report["claims"].as_array().unwrap();
    // Mikami's 1.5 % judged by proof: the proven bound beside the found value
    let mikami = claims
        .iter()
        .find(|c| c["method"] == "mikami_const")
        .unwrap();
    assert_eq!(mikami["basis"], "proven", "{mikami}");
    assert_eq!(mikami["verdict"], "agrees", "{mikami}");
    let (p, f) = (
        mikami["proven_upper"].as_f64().unwrap(),
        mikami["found"].as_f64().unwrap(),
    );
    assert!(f <= p && p <= 0.015, "{mikami}");
    // the found input is a stress case: --replay evaluates it again (f64 twin and device)
    let case = out.join("cases/newton_raphson_length_error.json");
    let (code, stdout, stderr) = run(&["stress", "--replay", case.to_str().unwrap()]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("method   newton_raphson"), "{stdout}");
}

#[test]
fn prove_refuses_a_bad_angle_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let (code, _, stderr) = run(&[
        "prove",
        "--max-angle",
        "200",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("--max-angle 200: expected degrees in (0, 180]"),
        "{stderr}"
    );
}
