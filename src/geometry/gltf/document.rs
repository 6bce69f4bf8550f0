//! The JSON document of a glTF file, on the `gltf` crate's types, where those are stricter than
//! the specification: the crate requires a scene's `nodes`, which glTF 2.0 makes optional
//! (section 5.26: a scene without it places nothing). Such a document is read as if each of
//! those scenes had `"nodes": []`, written into the text on the same line, so that every other
//! error keeps the line the crate gives it.
use ::gltf::json;

/// The document of `text`, or the crate's error (with its line) for the text as given, or
/// for the text with the missing `nodes` filled in when that was what failed first.
pub(super) fn parse(text: &[u8]) -> Result<json::Root, json::Error> {
    let first = match json::deserialize::from_slice(text) {
        Ok(root) => return Ok(root),
        Err(e) => e,
    };
    match scenes_without_nodes(text) {
        Some(at) if !at.is_empty() => json::deserialize::from_slice(&with_empty_nodes(text, &at)),
        _ => Err(first),
    }
}

/// `text` with `"nodes":[]` (and a comma before the object's other members) written just after
/// each `{` at `at`.
fn with_empty_nodes(text: &[u8], at: &[(usize, bool)]) -> Vec<u8> {
    let mut out = Vec::with_capacity(text.len() + at.len() * 12);
    let mut from = 0;
    for &(pos, empty) in at {
        out.extend_from_slice(&text[from..pos]);
        out.extend_from_slice(if empty {
            b"\"nodes\":[]"
        } else {
            b"\"nodes\":[],"
        });
        from = pos;
    }
    out.extend_from_slice(&text[from..]);
    out
}

/// For each object of the top-level `scenes` array without a `nodes` member: the offset just
/// after its `{` and whether it has no members at all. `None` when the text is not a JSON
/// object this scan can follow (the crate's own error then stands).
fn scenes_without_nodes(text: &[u8]) -> Option<Vec<(usize, bool)>> {
    let mut c = Scan { text, at: 0 };
    let mut found = Vec::new();
    c.expect(b'{')?;
    c.members(|c, key| {
        if key != b"scenes" {
            return c.skip_value();
        }
        c.expect(b'[')?;
        c.ws();
        if c.eat(b']') {
            return Some(());
        }
        loop {
            c.ws();
            if c.peek()? == b'{' {
                c.at += 1;
                let open = c.at;
                let (mut nodes, mut any) = (false, false);
                c.members(|c, key| {
                    any = true;
                    nodes |= key == b"nodes";
                    c.skip_value()
                })?;
                if !nodes {
                    found.push((open, !any));
                }
            } else {
                c.skip_value()?;
            }
            c.ws();
            if c.eat(b']') {
                return Some(());
            }
            c.expect(b',')?;
        }
    })?;
    Some(found)
}

/// A cursor over JSON text that follows its structure without building values.
struct Scan<'t> {
    text: &'t [u8],
    at: usize,
}

impl<'t> Scan<'t> {
    fn peek(&self) -> Option<u8> {
        self.text.get(self.at).copied()
    }

    fn ws(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.at += 1;
        }
    }

    fn eat(&mut self, b: u8) -> bool {
        let here = self.peek() == Some(b);
        self.at += usize::from(here);
        here
    }

    fn expect(&mut self, b: u8) -> Option<()> {
        self.ws();
        self.eat(b).then_some(())
    }

    /// A string's raw bytes between its quotes (escapes left as written).
    fn string(&mut self) -> Option<&'t [u8]> {
        self.expect(b'"')?;
        let start = self.at;
        loop {
            match self.peek()? {
                b'"' => break,
                b'\\' => self.at += 2,
                _ => self.at += 1,
            }
        }
        let s = self.text.get(start..self.at)?;
        self.at += 1;
        Some(s)
    }

    /// The members of an object whose `{` is read: `each` with the cursor on a member's
    /// value, which it must read; the cursor ends after the `}`.
    fn members(&mut self, mut each: impl FnMut(&mut Self, &'t [u8]) -> Option<()>) -> Option<()> {
        self.ws();
        if self.eat(b'}') {
            return Some(());
        }
        loop {
            let key = self.string()?;
            self.expect(b':')?;
            self.ws();
            each(self, key)?;
            self.ws();
            if self.eat(b'}') {
                return Some(());
            }
            self.expect(b',')?;
        }
    }

    /// Skips one value; nested objects and arrays by their brackets (an explicit depth, so a
    /// deeply nested file cannot overflow the stack).
    fn skip_value(&mut self) -> Option<()> {
        self.ws();
        match self.peek()? {
            b'"' => self.string().map(drop),
            b'{' | b'[' => {
                let mut depth = 0usize;
                loop {
                    match self.peek()? {
                        b'"' => {
                            self.string()?;
                            continue;
                        }
                        b'{' | b'[' => depth += 1,
                        b'}' | b']' => {
                            depth -= 1;
                            if depth == 0 {
                                self.at += 1;
                                return Some(());
                            }
                        }
                        _ => {}
                    }
                    self.at += 1;
                }
            }
            _ => {
                let start = self.at;
                while self
                    .peek()
                    .is_some_and(|b| !b"{}[],:\"".contains(&b) && !b.is_ascii_whitespace())
                {
                    self.at += 1;
                }
                (self.at > start).then_some(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_without_nodes_get_an_empty_list_on_the_same_line() {
        let text = b"{\"asset\":{\"version\":\"2.0\"},\"x\":[{\"a\":\"]}\\\"\"}],\n\"scenes\":[{}, {\"name\":\"s\"},\n{\"nodes\":[0]}]}";
        let at = scenes_without_nodes(text).unwrap();
        assert_eq!(at.len(), 2);
        let patched = String::from_utf8(with_empty_nodes(text, &at)).unwrap();
        assert!(
            patched.ends_with(
                "\"scenes\":[{\"nodes\":[]}, {\"nodes\":[],\"name\":\"s\"},\n{\"nodes\":[0]}]}"
            ),
            "{patched}"
        );
        let v: serde_json::Value = serde_json::from_str(&patched).unwrap();
        assert_eq!(v["scenes"][1]["name"], "s");
        // Not an object, or cut short: no scan, the crate's error stands.
        assert_eq!(scenes_without_nodes(b"[1]"), None);
        assert_eq!(scenes_without_nodes(b"{\"scenes\":[{}"), None);
    }
}
