//! The charts' error axes clamped to what carries information ([`crate::report::svg`]).
use crate::report::svg::{decades, Chart, Series};

/// An error axis stops at 1 and at 1e-9 however far a method blows up; a point beyond it is
/// drawn on the edge, marked, with its value in the legend; a point on it is not marked.
#[test]
fn error_axes_clamp_and_mark_what_lies_beyond() {
    assert_eq!(decades([2e-5, 1e9].into_iter()), (-5, 0));
    assert_eq!(decades([1e-13, 2e-3].into_iter()), (-9, -2));
    assert_eq!(decades([2e-3, 3e-2].into_iter()), (-3, -1));
    let one = |name: &str, y: Option<f64>| Series {
        name: name.into(),
        points: vec![(1.0, y, None)],
    };
    let chart = Chart {
        id: "c".into(),
        x_title: "x".into(),
        y_title: "y".into(),
        lines: false,
        x_range: (0.0, 2.0),
        y_decades: decades([2e-4, 1e9].into_iter()),
        h_rules: Vec::new(),
        v_rule: None,
        panels: vec![(
            "p".into(),
            vec![
                one("blows", Some(3e8)),
                one("fine", Some(1e-2)),
                one("nan", None),
                one("zero", Some(0.0)),
            ],
        )],
    };
    let h = chart.html("caption");
    assert!(h.contains("data-y-max=\"1e0\""), "{h}");
    // The off-scale points: marked, their values in their legends.
    assert_eq!(h.matches("class=\"pt off").count(), 3, "{h}");
    assert!(
        h.contains("data-y=\"3e8\"") && h.contains("\u{25b2}3e8"),
        "{h}"
    );
    assert!(h.contains("\u{d7}NaN") && h.contains("\u{25bc}0"), "{h}");
    // The point on the axis: a plain marker, no note.
    assert!(h.contains("<circle class=\"pt\" data-y=\"1e-2\""), "{h}");
    // Teeth: widen the axis to 1e9 and nothing is off it but the non-finite and the zero.
    let wide = Chart {
        y_decades: (-4, 9),
        ..chart
    };
    assert_eq!(wide.html("c").matches("class=\"pt off").count(), 2);
}
