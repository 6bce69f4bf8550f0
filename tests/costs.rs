//! The cost-model seam (src/cost/): a cost model made up here, a fixed table of figures for an
//! imaginary GPU, registered in this file alone, reaches every consumer: the report's answer
//! table and page, the seeds' speed claims of its benches, the corpus tables, and `auto
//! --cost-model`. Nothing outside this file names it.
use std::path::Path;

use shadelab::cost::{
    rule::static_cheaper, CostFigure, CostKind, CostModel, CostModelId, CostSource, Evidence,
    Measure, Registry,
};
use shadelab::method::{self, Method, Precision};

use crate::support::{read_json, run, validated_renderer};

/// The made-up model's id.
const ID: &str = "madeup:gpu";

/// Figures of an imaginary GPU, relative to phong_exact: only newton_raphson and gouraud are
/// cheaper; every other method costs 1.5 (so the answer can only be one of those two).
fn figure(m: &str) -> f64 {
    match m {
        "gouraud" => 0.25,
        "newton_raphson" => 0.5,
        "phong_exact" => 1.0,
        _ => 1.5,
    }
}

fn model(methods: impl IntoIterator<Item = String>) -> CostModel {
    CostModel {
        id: CostModelId::parse(ID).unwrap(),
        title: "made-up GPU (static)".into(),
        kind: CostKind::Static,
        measure: Measure {
            statistic: "a fixed table".into(),
            unit: "made-up cycles".into(),
        },
        description: "a fixed table of figures, for the seam's test".into(),
        precision: Precision::F32,
        figures: methods
            .into_iter()
            .map(|m| {
                let r = figure(&m);
                CostFigure {
                    value: Some(100.0 * r),
                    ratio: Some(r),
                    ci95_low: None,
                    ci95_high: None,
                    verdict: static_cheaper(Some(r)),
                    evidence: String::new(),
                    note: "made up".into(),
                    method: m,
                }
            })
            .collect(),
        pairs: Vec::new(),
    }
}

struct MadeUp;

impl CostSource for MadeUp {
    fn name(&self) -> &'static str {
        "madeup"
    }

    fn models(&self, _ev: &Evidence) -> Vec<CostModel> {
        vec![model(method::all().iter().map(|m| m.name.to_string()))]
    }

    fn on_demand(&self) -> Option<&'static str> {
        Some(ID)
    }

    fn measures(&self, id: &CostModelId) -> bool {
        *id == *ID
    }

    fn measure(
        &self,
        _id: &CostModelId,
        methods: &[&'static Method],
        _ev: &Evidence,
    ) -> shadelab::Result<CostModel> {
        Ok(model(methods.iter().map(|m| m.name.to_string())))
    }
}

fn registry() -> Registry {
    shadelab::costs::builtin().with(MadeUp)
}

fn methods() -> Vec<&'static Method> {
    ["gouraud", "newton_raphson", "lyon_taylor"]
        .iter()
        .map(|n| method::find(n).unwrap())
        .collect()
}

/// The report: its answer table has the model's row with the cheaper method that meets the
/// budget, its page shows it, and each scene's bench judges the speed claims under it.
#[test]
fn a_registered_cost_model_reaches_the_report_and_the_speed_claims() {
    let dir = tempfile::tempdir().unwrap();
    let r = validated_renderer();
    let scene = crate::support::shipped_scene("sphere_fine", 40);
    let scenes = vec![shadelab::report::ReportScene {
        source: Path::new("scenes/sphere_fine.toml").into(),
        scene,
        load: Default::default(),
    }];
    let opts = shadelab::report::ReportOptions {
        full: false,
        command_line: "test".into(),
        progress: false,
        schedule: shadelab::bench::schedule::Schedule::new(
            shadelab::bench::schedule::Job::Report { full: false },
            &shadelab::bench::schedule::Given {
                runs: Some(1),
                ..Default::default()
            },
        )
        .unwrap(),
        exe: None,
        device: Default::default(),
        costs: registry(),
        tuned: None,
    };
    let out = dir.path().join("r");
    shadelab::report::run(&r, &scenes, &methods(), &out, &opts).unwrap();
    let answer = read_json(out.join("answer.json"));
    let m = answer["cost_models"]
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == ID)
        .expect("the made-up model in answer.json");
    assert_eq!(m["measure"]["unit"], "made-up cycles");
    // 4/255 is met by newton_raphson on the fine sphere (gouraud errs more):
    // whichever answers, it is one the table calls cheaper, and the text says so.
    let cell = answer["cells"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["cost_model"] == ID && c["budget"] == "max_4_255")
        .unwrap();
    let chosen = cell["answer"]["method"].as_str().unwrap();
    assert!(["gouraud", "newton_raphson"].contains(&chosen), "{cell}");
    assert_eq!(cell["answer"]["ratio"].as_f64(), Some(figure(chosen)));
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        html.contains(&format!("data-model=\"{ID}\"")),
        "no row in the page"
    );
    assert!(html.contains("made-up GPU (static)"));
    // The bench's speed claims have the model's column, judged by its ratio.
    let bench = read_json(out.join("scenes/sphere_fine/bench/bench.json"));
    let claims = bench["speed_claims"].as_array().unwrap();
    let nr = claims
        .iter()
        .find(|c| c["num"] == "newton_raphson" && c["den"] == "phong_exact")
        .expect("newton_raphson's speed claim");
    let col = nr["cells"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["cost_model"] == ID)
        .expect("the made-up column");
    assert_eq!(col["ratio"].as_f64(), Some(0.5), "{col}");
    assert!(col["ci95_low"].is_null());
    // Teeth: the built-in registry alone has no such row.
    let plain = shadelab::costs::builtin().models(&Evidence::new());
    assert!(plain.iter().all(|m| m.id != *ID));
}

/// `auto --cost-model` orders its candidates by the model (gouraud 0.25, newton_raphson 0.5,
/// the rest 1.5; phong_exact last, the fallback), and the corpus tables answer under it.
#[test]
fn a_registered_cost_model_ranks_auto_and_answers_a_corpus() {
    let id = CostModelId::parse(ID).unwrap();
    let (order, m) = shadelab::auto::order_by_model(&registry(), &id, &Evidence::new()).unwrap();
    let names: Vec<&str> = order.iter().map(|(m, _)| m.name).collect();
    assert_eq!(names[..2], ["gouraud", "newton_raphson"], "{names:?}");
    assert_eq!(names.last(), Some(&"phong_exact"));
    assert_eq!(order[0].1, 25.0, "the figure in the model's unit");
    assert_eq!(m.measure.unit, "made-up cycles");
    // Teeth: the built-in registry does not know the id.
    assert!(
        shadelab::auto::order_by_model(&shadelab::costs::builtin(), &id, &Evidence::new()).is_err()
    );

    let dir = tempfile::tempdir().unwrap();
    let corpus = dir.path().join("meshes");
    std::fs::create_dir_all(&corpus).unwrap();
    std::fs::copy("scenes/icosphere.obj", corpus.join("ico.obj")).unwrap();
    let shard = dir.path().join("shard");
    let (code, _, err) = run(&[
        "corpus",
        corpus.to_str().unwrap(),
        "--out",
        shard.to_str().unwrap(),
        "--size",
        "32x32",
        "--methods",
        "gouraud,newton_raphson",
        "--no-isa",
    ]);
    assert_eq!(code, 0, "{err}");
    let shards = shadelab::corpus::merge::check(&[shard]).unwrap();
    let meshes = shadelab::corpus::merge::gather(&shards).unwrap();
    let report = shadelab::corpus::tables::report(&shards, &meshes, None, &registry());
    let out = dir.path().join("merged");
    shadelab::corpus::tables::write(&out, &report, &meshes).unwrap();
    let json = read_json(out.join("corpus.json"));
    let cells: Vec<&serde_json::Value> = json["answer"]["cells"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["cost_model"] == ID)
        .collect();
    assert_eq!(cells.len(), 6, "a cell per budget");
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(html.contains("made-up GPU (static)"), "the corpus page");
}

/// A second made-up model, `madeup:tuned`: the tuned row `tuned_cheap` costs 0.1 of
/// phong_exact, everything else 1.5 (phong_exact 1).
struct TunedCheap;

const TUNED_ID: &str = "madeup:tuned";

impl CostSource for TunedCheap {
    fn name(&self) -> &'static str {
        "madeup_tuned"
    }

    fn models(&self, _ev: &Evidence) -> Vec<CostModel> {
        Vec::new()
    }

    fn on_demand(&self) -> Option<&'static str> {
        Some(TUNED_ID)
    }

    fn measures(&self, id: &CostModelId) -> bool {
        *id == *TUNED_ID
    }

    fn measure(
        &self,
        _id: &CostModelId,
        methods: &[&'static Method],
        _ev: &Evidence,
    ) -> shadelab::Result<CostModel> {
        let mut m = model(methods.iter().map(|m| m.name.to_string()));
        m.id = CostModelId::parse(TUNED_ID).unwrap();
        for f in &mut m.figures {
            let r = match f.method.as_str() {
                "tuned_cheap" => 0.1,
                "phong_exact" => 1.0,
                _ => 1.5,
            };
            f.value = Some(100.0 * r);
            f.ratio = Some(r);
            f.verdict = static_cheaper(Some(r));
        }
        Ok(m)
    }
}

/// `auto` draws a tuned row (a `shadelab tune` file through `--method-file`) where it is the
/// cheapest within the budget: under a model that makes it cheapest it comes first, and on
/// the torus every triangle inside its proven domain whose samples pass draws it.
#[test]
fn auto_draws_a_tuned_row_where_it_is_the_cheapest_within_budget() {
    use shadelab::method::tuned::{Tuned, TunedForm};
    let dir = tempfile::tempdir().unwrap();
    let t = Tuned {
        form: TunedForm::Newton,
        steps: 3,
        coeffs: vec![1.5, -0.5],
        domain: [0.5, 1.0001],
        length_error: None,
    };
    let file = dir.path().join("tuned_cheap.glsl");
    std::fs::write(&file, format!("{}\n{}", t.line(), t.code())).unwrap();
    shadelab::gpu::shaders::register_user(&[file]).unwrap();
    let registry = shadelab::costs::builtin().with(TunedCheap);
    let id = CostModelId::parse(TUNED_ID).unwrap();
    let (order, _) = shadelab::auto::order_by_model(&registry, &id, &Evidence::new()).unwrap();
    let order: Vec<&'static Method> = order.iter().map(|(m, _)| *m).collect();
    assert_eq!(order[0].name, "tuned_cheap", "the cheapest comes first");
    let scene = shadelab::scene::load_scene(Path::new("scenes/torus.toml")).unwrap();
    let inputs = shadelab::scene::SceneInputs::new(&scene, shadelab::method::Geometry::Mesh);
    let pick = shadelab::auto::choose(&inputs, &order, 1.0 / 255.0);
    let drawn = pick.iter().filter(|&&k| k == 0).count();
    assert_eq!(
        drawn,
        inputs.triangle_count(),
        "inside its domain everywhere"
    );
}
