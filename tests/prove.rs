//! `shadelab prove`: proof.json against its schema (with teeth), its two domains, the bounds
//! above the found values, the methods out of reach listed, the found inputs (a triangle's and
//! an edge's) replayed by `stress --replay`, the help naming the angle's domain, and the exact
//! error texts of bad input.
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
        "/methods/0/domains/0/colour",
        "proven_upper",
    );
    let domains: Vec<_> = report["domains"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["name"].as_str().unwrap())
        .collect();
    assert_eq!(domains, ["triangle", "edge"]);
    let methods = report["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 2);
    for m in methods {
        let mut length = Vec::new();
        for (d, name) in m["domains"].as_array().unwrap().iter().zip(&domains) {
            assert_eq!(d["domain"], *name, "{d}");
            for x in d["metrics"].as_array().unwrap() {
                let (p, f) = (
                    x["proven_upper"].as_f64().unwrap(),
                    x["found"].as_f64().unwrap(),
                );
                assert!(f <= p + 1e-12, "{x}");
            }
            length.push(d["metrics"][0]["proven_upper"].as_f64().unwrap());
            let c = &d["colour"];
            assert!(c["found"].as_f64().unwrap() <= c["proven_upper"].as_f64().unwrap());
        }
        // the edge is a part of the triangle domain (each bound within 1 % of a real point);
        // stress's grid is of edges
        assert!(length[0] * 1.01 + 1e-12 >= length[1], "{m}");
        assert_eq!(m["stress_grid"]["domain"], "edge");
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
    // the found inputs are stress cases: --replay evaluates them again (f64 twin and device),
    // a triangle's too (N2 off the bisector, a pixel inside the strip)
    for domain in ["triangle", "edge"] {
        let case = out.join(format!("cases/newton_raphson_{domain}_length_error.json"));
        let (code, stdout, stderr) = run(&["stress", "--replay", case.to_str().unwrap()]);
        assert_eq!(code, 0, "{stdout}{stderr}");
        assert!(stdout.contains("method   newton_raphson"), "{stdout}");
    }
}

#[test]
fn prove_help_names_the_domain_of_its_angle() {
    let (code, stdout, stderr) = run(&["prove", "--help"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("Largest angle between any two vertex normals")
            && stdout.contains("any triangle"),
        "{stdout}"
    );
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
