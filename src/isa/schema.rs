//! The per-vendor rules of docs/isa.schema.json, generated from the registered routes: each
//! route's [`Vendor::required_statistics`] is what its rows must carry. A new route is its
//! file and its line in [`super::route::VENDORS`]; its schema rule follows from them (a test
//! compares the file with [`vendor_rules`], and `SHADELAB_BLESS=1` writes it).
use super::route::{Vendor, VENDORS};

/// The line that opens the rules in docs/isa.schema.json, and the one that closes them.
pub const OPEN: &str = "        \"allOf\": [\n";
pub const CLOSE: &str = "\n        ]\n";

/// The rule of one vendor: a row whose family starts with its prefix requires its statistics.
fn rule(v: &dyn Vendor) -> String {
    let required: Vec<String> = v
        .required_statistics()
        .iter()
        .map(|k| format!("\"{k}\""))
        .collect();
    format!(
        "          {{ \"if\": {{ \"properties\": {{ \"family\": {{ \"pattern\": \"^{}:\" }} }} }},\n            \
         \"then\": {{ \"properties\": {{ \"statistics\": {{ \"required\": [{}] }} }} }} }}",
        v.prefix(),
        required.join(", ")
    )
}

/// The rule of a vendor's draw rows (its [`Vendor::required_draw_statistics`]), where it has
/// one.
fn draw_rule(v: &dyn Vendor) -> Option<String> {
    let required: Vec<String> = v
        .required_draw_statistics()
        .iter()
        .map(|k| format!("\"{k}\""))
        .collect();
    (!required.is_empty()).then(|| {
        format!(
            "          {{ \"if\": {{ \"properties\": {{ \"family\": {{ \"pattern\": \"^{}:\" }}, \"kind\": {{ \"const\": \"draw\" }} }} }},\n            \
             \"then\": {{ \"properties\": {{ \"statistics\": {{ \"required\": [{}] }} }} }} }}",
            v.prefix(),
            required.join(", ")
        )
    })
}

/// The text between [`OPEN`] and [`CLOSE`]: every route's rule, then its draw rows' rule where
/// it has one, in the routes' order.
pub fn vendor_rules_of(vendors: &[&dyn Vendor]) -> String {
    vendors
        .iter()
        .flat_map(|v| std::iter::once(rule(*v)).chain(draw_rule(*v)))
        .collect::<Vec<_>>()
        .join(",\n")
}

/// [`vendor_rules_of`] the registered routes.
pub fn vendor_rules() -> String {
    vendor_rules_of(&VENDORS)
}

/// Where the rules of `schema` (the file's text) lie: between [`OPEN`] and [`CLOSE`].
fn span(schema: &str) -> Option<std::ops::Range<usize>> {
    let start = schema.find(OPEN)? + OPEN.len();
    Some(start..start + schema[start..].find(CLOSE)?)
}

/// `schema` with its rules replaced by `rules`; `None` when the file has no rules block.
pub fn with_rules(schema: &str, rules: &str) -> Option<String> {
    let r = span(schema)?;
    Some(format!("{}{rules}{}", &schema[..r.start], &schema[r.end..]))
}

/// The rules block of `schema`, as text.
pub fn rules_in(schema: &str) -> Option<&str> {
    Some(&schema[span(schema)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_route_has_a_rule_with_its_statistics_and_the_text_is_json() {
        let rules = vendor_rules();
        let v: serde_json::Value = serde_json::from_str(&format!("[{rules}]")).unwrap();
        let mut rules_left = v.as_array().unwrap().iter();
        for vendor in VENDORS {
            let r = rules_left.next().unwrap();
            assert_eq!(
                r["if"]["properties"]["family"]["pattern"],
                format!("^{}:", vendor.prefix())
            );
            assert_eq!(
                r["then"]["properties"]["statistics"]["required"],
                serde_json::json!(vendor.required_statistics())
            );
            // Then its draw rows' rule, where it has one.
            if !vendor.required_draw_statistics().is_empty() {
                let d = rules_left.next().unwrap();
                assert_eq!(d["if"]["properties"]["kind"]["const"], "draw");
                assert_eq!(
                    d["then"]["properties"]["statistics"]["required"],
                    serde_json::json!(vendor.required_draw_statistics())
                );
            }
        }
        assert!(rules_left.next().is_none());
        // Mali reports no registers: no draw rule; AMD's requires its waves.
        assert!(super::super::route::arm::Arm
            .required_draw_statistics()
            .is_empty());
        assert_eq!(
            super::super::route::amd::Amd.required_draw_statistics(),
            [
                crate::isa::occupancy::REGISTERS_KEY,
                crate::isa::occupancy::WAVES_KEY
            ]
        );
        // Teeth: one route fewer is other text.
        assert_ne!(vendor_rules_of(&VENDORS[..VENDORS.len() - 1]), rules);
    }

    #[test]
    fn the_rules_block_is_replaced_in_place() {
        let schema = format!("{{\n{OPEN}          old{CLOSE}}}\n");
        assert_eq!(rules_in(&schema), Some("          old"));
        let new = with_rules(&schema, "          new").unwrap();
        assert_eq!(new, format!("{{\n{OPEN}          new{CLOSE}}}\n"));
        assert_eq!(with_rules("{}", "x"), None);
    }
}
