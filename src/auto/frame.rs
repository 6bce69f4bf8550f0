//! `auto`'s frame check on the run's device: the per-triangle choice, settled by the cost
//! model ([`crate::auto::settle_on`]), is drawn grouped only when it measured cheaper than
//! drawing every triangle with the one program, both timed in the same interleaved rounds
//! (the order alternating per round, as bench's rounds do for two programs); otherwise auto
//! draws one program and says so ([`crate::auto::FrameCheck`]). Every command that draws
//! `auto` with Vulkan (render, compare, bench, skips) goes through [`choose_checked`]; a run of
//! a bench of several runs draws its parent's decision ([`decisions`], in its request) so that
//! every run times the same draw.
use crate::analysis::stats::{paired_ratio, RatioEstimate};
use crate::auto::{AutoSpec, AutoSummary, Cache, FrameCheck};
use crate::error::Result;
use crate::gpu::{AutoScene, Renderer};
use crate::scene::{Scene, SceneInputs};

/// Rounds of the check (each times both draws once), after [`CHECK_WARMUP`] discarded
/// submissions of each: 16 rounds give a sign-test 95% interval between the 4th and 13th
/// ratios.
pub const CHECK_ROUNDS: usize = 16;
pub const CHECK_WARMUP: usize = 2;

/// The frame checks' decisions of `summaries` (specs whose grouping was checked): (spec
/// name, grouped), what a bench of several runs gives its runs so that every run times the
/// same draw.
pub fn decisions(summaries: &[AutoSummary]) -> Vec<(String, bool)> {
    summaries
        .iter()
        .filter_map(|s| Some((s.name.clone(), s.grouping.as_ref()?.frame.as_ref()?.grouped)))
        .collect()
}

/// `spec`'s choice on `inputs` (`scene` uploaded), settled by the model and then by the frame
/// check: the triangles' methods, the summary, and the uploaded draw. `given`: the decision of
/// the parent of a bench run (grouped or not), drawn without timing.
pub fn choose_checked(
    renderer: &Renderer,
    scene: &Scene,
    inputs: &SceneInputs,
    spec: &AutoSpec,
    cache: Cache,
    given: Option<bool>,
) -> Result<(Vec<usize>, AutoSummary, AutoScene)> {
    let (mut pick, mut summary) = crate::auto::choose_summarised(inputs, spec, cache);
    let grouped = renderer.prepare_auto(scene, &spec.order, &pick)?;
    let Some((single, predicted)) = summary
        .grouping
        .as_ref()
        .filter(|g| g.programs_drawn > 1)
        .and_then(|g| Some((g.single_index(spec)?, g.predicted_saving())))
    else {
        return Ok((pick, summary, grouped));
    };
    // The one program alone, with only its own vertex streams and the scene's triangle order:
    // the same draw as `render --method <it>` (a fallback that uploads every candidate's
    // streams measured 2.6 % slower than that draw on suzanne).
    let one = renderer.prepare_auto(scene, &spec.order[single..=single], &vec![0; pick.len()])?;
    let check = match given {
        Some(keep) => FrameCheck::given(keep, predicted),
        None => {
            log::info!(
                "auto: frame check of {}: its {} programs against {} alone, {} rounds",
                spec.name,
                summary.grouping.as_ref().map_or(0, |g| g.programs_drawn),
                spec.order[single].name,
                CHECK_ROUNDS
            );
            FrameCheck::measured(&time_pair(renderer, &grouped, &one)?, predicted)
        }
    };
    let keep = crate::auto::apply_frame_check(spec, &mut pick, &mut summary, check);
    Ok((pick, summary, if keep { grouped } else { one }))
}

/// `a`'s frame over `b`'s per round, both drawn as timed (the timed draw's targets and
/// pre-pass), after [`CHECK_WARMUP`] discarded submissions each, in [`CHECK_ROUNDS`] rounds
/// whose order alternates (a then b, then b then a), wall clock.
fn time_pair(renderer: &Renderer, a: &AutoScene, b: &AutoScene) -> Result<RatioEstimate> {
    let draws = renderer.timed_draw_lists(&[a.draw_list(), b.draw_list()])?;
    for i in [0, 1] {
        for _ in 0..CHECK_WARMUP {
            draws.run(i)?;
        }
    }
    let mut v = [Vec::new(), Vec::new()];
    for r in 0..CHECK_ROUNDS {
        for i in [r % 2, 1 - r % 2] {
            v[i].push(draws.run(i)?.wall_ms);
        }
    }
    Ok(paired_ratio(&v[0], &v[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a parent measured is what its runs read back, per spec; a spec without a check
    /// (one program anyway) is left out.
    #[test]
    fn the_parent_writes_each_checked_decision() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
        let scene = crate::scene::load_scene(&path).unwrap();
        let inputs = SceneInputs::new(&scene, crate::method::Geometry::Mesh);
        let order: Vec<(&'static crate::method::Method, f64)> = [
            crate::method::vertex_lit_reference(),
            crate::method::find("newton_raphson").unwrap(),
            crate::method::phong_exact(),
        ]
        .into_iter()
        .zip([0.1, 1.0, 1.0])
        .collect();
        let spec = AutoSpec::new(crate::auto::ErrorBudget::DEFAULT, &order);
        let summary = |keep: bool, name: &str| {
            let (mut pick, mut s) = crate::auto::choose_summarised(&inputs, &spec, Cache::Bypass);
            crate::auto::apply_frame_check(&spec, &mut pick, &mut s, FrameCheck::given(keep, 0.5));
            s.name = name.into();
            s
        };
        let mut plain = summary(true, "auto_16_255");
        plain.grouping.as_mut().unwrap().frame = None;
        let given = decisions(&[summary(false, "auto"), summary(true, "auto_1_1024"), plain]);
        assert_eq!(
            given,
            [
                ("auto".to_string(), false),
                ("auto_1_1024".to_string(), true)
            ]
        );
    }
}
