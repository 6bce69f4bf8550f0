//! The answer in words ([`crate::report::summary`]) and tune's findings in the cells
//! ([`crate::report::tuned`]), on the fixture of `answer_rule` (two scenes; fast, faster,
//! rough).
use super::*;
use crate::report::summary::Common;
use crate::report::tuned::Tuned;

fn inputs<'a>(
    scenes: &'a [String],
    names: &'a [String],
    errors: &'a [SceneError],
    models: Vec<CostModel>,
    tuned: Option<Tuned>,
) -> Inputs<'a> {
    Inputs {
        scenes,
        methods: names,
        errors,
        models,
        scene_models: Vec::new(),
        tuned,
        missing: Vec::new(),
    }
}

/// faster answers 4 of the 6 cells; max 1/1024 (nothing cheaper: fast fails on b) and p99
/// 1/1024 (fast) differ, and say so; scene a alone lets fast meet max 1/1024.
#[test]
fn the_words_state_the_common_answer_and_what_differs() {
    let a = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
    let s = &a.summary;
    assert_eq!(
        s.common,
        Common {
            method: "faster".into(),
            nothing_cheaper: false,
            cells: 4,
            of: 6
        }
    );
    let differ: Vec<String> = s.differing.iter().map(|c| c.budget.id()).collect();
    assert_eq!(differ, ["max_1_1024", "p99_1_1024"]);
    assert!(
        s.sentences[0].starts_with("faster is the cheapest method in 4 of the 6 cells"),
        "{:?}",
        s.sentences
    );
    assert_eq!(s.sentences.len(), 2, "{:?}", s.sentences);
    assert!(
        s.sentences[1].starts_with("Scene by scene the answer differs on 2 of the 2 scenes (a and b); most widely on a, where fast is cheaper within"),
        "{}",
        s.sentences[1]
    );
    let on = |scene: &str, budget: &str| {
        let sb = (s.per_scene.iter())
            .find(|x| x.scene == scene && x.budget.id() == budget)
            .unwrap();
        (sb.answers[0].method.clone(), sb.answers[0].nothing_cheaper)
    };
    assert_eq!(on("a", "max_1_1024"), ("fast".into(), false));
    assert_eq!(on("b", "max_1_1024"), ("phong_exact".into(), true));
    assert_eq!(on("a", "max_1_255"), ("faster".into(), false));
    // Teeth: where nothing is cheaper anywhere, the words say so of every cell, none differ.
    let dear: Vec<CostFigure> = (figures().into_iter())
        .map(|f| {
            let r = if f.method == "phong_exact" { 1.0 } else { 1.5 };
            fig(&f.method, r, r - 0.1, r + 0.1)
        })
        .collect();
    let a = answer(&scenes(), &names(), &errors(), vec![model(dear)]);
    assert!(a.summary.differing.is_empty());
    assert!(
        a.summary.sentences[0].starts_with(
            "Nothing is cheaper than phong_exact within every one of the 6 error budgets"
        ),
        "{:?}",
        a.summary.sentences
    );
    assert_eq!(
        a.summary.sentences[1],
        "Scene by scene the answer is the same on every scene."
    );
}

/// An interval model's cell where a method within the budget is neither measured cheaper nor
/// dearer than the answer is unresolved, says what would resolve it, and the words count it;
/// a static model with the same figures is never unresolved.
#[test]
fn an_interval_that_cannot_tell_leaves_the_cell_unresolved() {
    let mut figs = figures();
    figs[2] = fig("faster", 0.7, 0.5, 1.1);
    let a = answer(&scenes(), &names(), &errors(), vec![model(figs.clone())]);
    let c = cell(&a, "max_1_255", "m").unwrap();
    assert_eq!(c.answer.method, "fast");
    assert_eq!(c.unresolved, ["faster"]);
    assert!(
        c.text.contains("unresolved at this size: 1 method"),
        "{}",
        c.text
    );
    assert!(c.text.contains("--runs"), "{}", c.text);
    let n = a.cells.iter().filter(|c| !c.unresolved.is_empty()).count();
    assert!(n > 0 && a.summary.unresolved.len() == n);
    let said = format!("unresolved at this size in {n} of its 6 cells");
    assert!(
        a.summary.sentences.last().unwrap().contains(&said),
        "{said}: {:?}",
        a.summary.sentences
    );
    // Teeth: a resolved interval (faster wholly below fast's) leaves no cell unresolved.
    let a = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
    assert!(a.cells.iter().all(|c| c.unresolved.is_empty()));
    // A static model is never inconclusive, so never unresolved.
    let mut m = model(figs);
    m.kind = CostKind::Static;
    let a = answer(&scenes(), &names(), &errors(), vec![m]);
    assert!(a.cells.iter().all(|c| c.unresolved.is_empty()));
}

const TUNE_JSON: &str = r#"{"budget": 0.003, "cost_models": [
  {"model": "m", "cheapest": {"candidate": "rsqrt_p2", "label": "minimax degree 2",
   "ratio": 0.8, "colour_bound": 0.0029}},
  {"model": "other"}]}"#;

/// tune's winner shows in every cell whose budget holds tune's bound, under its cost model,
/// and in the words; a tune.json without a positive budget is refused.
#[test]
fn a_tuned_winner_shows_where_its_bound_fits_the_budget() {
    let path = std::path::Path::new("tune.json");
    let t = Tuned::parse(TUNE_JSON, "tune/tune.json", path).unwrap();
    assert_eq!(
        (t.wins.len(), t.none.clone()),
        (1, vec![CostModelId::parse("other").unwrap()])
    );
    let (s, n, e) = (scenes(), names(), errors());
    let a = answer_with(inputs(&s, &n, &e, vec![model(figures())], Some(t)));
    let with: Vec<String> = (a.cells.iter())
        .filter(|c| c.tuned.is_some())
        .map(|c| c.budget.id())
        .collect();
    // 0.003 fits 1/255 (0.0039) and 4/255, not 1/1024 (0.00098).
    assert_eq!(with, ["max_1_255", "max_4_255", "p99_1_255", "p99_4_255"]);
    let c = cell(&a, "max_1_255", "m").unwrap();
    assert!(
        c.text
            .contains("a tuned approximation beats exact normalisation here: rsqrt_p2"),
        "{}",
        c.text
    );
    assert!(
        (a.summary.sentences.iter()).any(|s| s.contains("A tuned approximation proven within")),
        "{:?}",
        a.summary.sentences
    );
    // Teeth: no budget, a negative one, not JSON.
    for bad in [r#"{"cost_models": []}"#, r#"{"budget": -1}"#, "budget"] {
        assert!(Tuned::parse(bad, "x", path).is_err(), "{bad}");
    }
}

/// answer.md opens with the words, then the cells that differ, then the grid; the terminal
/// shows the words and the differing cells in a few lines, never one line per cell.
#[test]
fn answer_md_and_the_terminal_open_with_the_words() {
    let a = answer(&scenes(), &names(), &errors(), vec![model(figures())]);
    assert!(
        !a.summary.differing.is_empty(),
        "the fixture has differing cells"
    );
    let md = a.markdown();
    let body = md.strip_prefix("# Which method to use\n\n").unwrap();
    assert!(body.starts_with(&a.summary.sentences[0]), "{md}");
    let differ = md.find("Cells that differ").expect("the differing cells");
    let grid = md.find("| cost model |").expect("the grid");
    assert!(differ < grid, "{md}");
    let t = a.terminal();
    assert!(t.lines().count() <= 15, "{t}");
    assert!(t.lines().all(|l| l.chars().count() <= 100), "{t}");
    let flat = t.split_whitespace().collect::<Vec<_>>().join(" ");
    for w in &a.summary.sentences {
        assert!(flat.contains(w.as_str()), "{w:?} not in {t}");
    }
    assert!(
        flat.contains("Cells that differ from the common answer (2)"),
        "{t}"
    );
    // Teeth: the per-cell lines (-v) are not the terminal text, and have one line per cell.
    assert!(!t.contains("answer: "), "{t}");
    assert_eq!(a.lines().lines().count(), a.cells.len());
}

/// However many cost models differ, the terminal lists a few groups and says how many more.
#[test]
fn the_terminal_caps_the_differing_cells() {
    let models: Vec<CostModel> = (0..9)
        .map(|k| {
            let mut m = model(figures());
            m.id = crate::cost::CostModelId::parse(&format!("m{k}")).unwrap();
            m.title = format!("model {k}");
            m
        })
        .collect();
    let a = answer(&scenes(), &names(), &errors(), models);
    let groups = a.summary.differing.len();
    assert!(groups > 4, "{groups}");
    let t = a.terminal();
    assert!(t.lines().count() <= 15, "{t}");
    assert!(t.contains("more (answer.md)"), "{t}");
}
