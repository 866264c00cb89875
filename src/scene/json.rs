//! Where a field is in a JSON scene's text, for its errors: serde_json gives the line and
//! column of a parse error but not the field, and its values carry no position for the
//! checks' errors (TOML's have both, through `toml_edit`'s spans). A small scanner reads
//! the text into the spans of its keys and values ([`Node`]), tolerant of a text that stops
//! or goes wrong midway (a syntax error: what was read before it is kept), and nested at
//! most [`MAX_DEPTH`] deep (serde_json refuses deeper texts itself).

use super::{FieldPath, Seg};

/// How deep the scanner follows nested arrays and objects (serde_json's own limit is 128).
const MAX_DEPTH: usize = 256;

/// A JSON value and its byte span `start..end` in the text.
struct Node {
    start: usize,
    end: usize,
    kind: Kind,
}

/// What a [`Node`] holds.
enum Kind {
    /// Its members: key, the key's span, the value (none where the text stops after the key).
    Object(Vec<(String, std::ops::Range<usize>, Option<Node>)>),
    /// Its elements.
    Array(Vec<Node>),
    /// A string, a number, `true`, `false` or `null`.
    Scalar,
}

/// The scanner over the text's bytes.
struct Scanner<'a> {
    text: &'a [u8],
    pos: usize,
}

impl Scanner<'_> {
    fn skip_space(&mut self) {
        while self.pos < self.text.len() && self.text[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&self) -> Option<u8> {
        self.text.get(self.pos).copied()
    }

    /// The value at the current position (after white space); `None` at the end of the text
    /// or where no value starts.
    fn value(&mut self, depth: usize) -> Option<Node> {
        self.skip_space();
        let start = self.pos;
        let kind = match self.peek()? {
            b'{' if depth < MAX_DEPTH => Kind::Object(self.object(depth)),
            b'[' if depth < MAX_DEPTH => Kind::Array(self.array(depth)),
            b'"' => {
                self.string();
                Kind::Scalar
            }
            b',' | b':' | b']' | b'}' => return None,
            _ => {
                while self.peek().is_some_and(|c| {
                    !matches!(c, b',' | b']' | b'}' | b':') && !c.is_ascii_whitespace()
                }) {
                    self.pos += 1;
                }
                Kind::Scalar
            }
        };
        Some(Node {
            start,
            end: self.pos,
            kind,
        })
    }

    /// A string from its opening quote: its text (escapes other than `\"` and `\\` kept
    /// as written: a key of the scene has none).
    fn string(&mut self) -> String {
        self.pos += 1;
        let mut out = Vec::new();
        while let Some(c) = self.peek() {
            self.pos += 1;
            match c {
                b'"' => break,
                b'\\' => {
                    if let Some(e) = self.peek() {
                        self.pos += 1;
                        if !matches!(e, b'"' | b'\\') {
                            out.push(b'\\');
                        }
                        out.push(e);
                    }
                }
                c => out.push(c),
            }
        }
        String::from_utf8_lossy(&out).into_owned()
    }

    /// An object's members, from its `{` to its `}` (or as far as the text goes well).
    fn object(&mut self, depth: usize) -> Vec<(String, std::ops::Range<usize>, Option<Node>)> {
        self.pos += 1;
        let mut members = Vec::new();
        loop {
            self.skip_space();
            match self.peek() {
                Some(b'}') => {
                    self.pos += 1;
                    return members;
                }
                Some(b',') => self.pos += 1,
                Some(b'"') => {
                    let start = self.pos;
                    let key = self.string();
                    let span = start..self.pos;
                    self.skip_space();
                    if self.peek() != Some(b':') {
                        members.push((key, span, None));
                        return members;
                    }
                    self.pos += 1;
                    let value = self.value(depth + 1);
                    let stop = value.is_none();
                    members.push((key, span, value));
                    if stop {
                        return members;
                    }
                }
                _ => return members,
            }
        }
    }

    /// An array's elements, from its `[` to its `]` (or as far as the text goes well).
    fn array(&mut self, depth: usize) -> Vec<Node> {
        self.pos += 1;
        let mut elements = Vec::new();
        loop {
            self.skip_space();
            match self.peek() {
                Some(b']') => {
                    self.pos += 1;
                    return elements;
                }
                Some(b',') => self.pos += 1,
                None => return elements,
                Some(_) => match self.value(depth + 1) {
                    Some(v) => elements.push(v),
                    None => return elements,
                },
            }
        }
    }
}

/// The scene's top value, as far as its text can be read.
fn parse(text: &str) -> Option<Node> {
    Scanner {
        text: text.as_bytes(),
        pos: 0,
    }
    .value(0)
}

/// Whether the span `start..end` holds the byte `offset` (an empty span its start).
fn holds(start: usize, end: usize, offset: usize) -> bool {
    start <= offset && offset < end.max(start + 1)
}

/// The path of the deepest key or value of a JSON text that holds byte `offset` (empty at
/// the top level): where serde_json's error at `offset` is.
pub(super) fn path_at(text: &str, offset: usize) -> FieldPath {
    let mut path = FieldPath::default();
    let mut node = parse(text);
    while let Some(n) = node.take() {
        match n.kind {
            Kind::Object(members) => {
                for (key, span, value) in members {
                    if holds(span.start, span.end, offset) {
                        path.0.push(Seg::Key(key));
                        return path;
                    }
                    if let Some(v) = value.filter(|v| holds(v.start, v.end, offset)) {
                        path.0.push(Seg::Key(key));
                        node = Some(v);
                        break;
                    }
                }
            }
            Kind::Array(elements) => {
                for (i, v) in elements.into_iter().enumerate() {
                    if holds(v.start, v.end, offset) {
                        path.0.push(Seg::Index(i));
                        node = Some(v);
                        break;
                    }
                }
            }
            Kind::Scalar => {}
        }
    }
    path
}

/// The start offset of the deepest part of `path` found in a JSON text: the key of a member,
/// the element of an array.
pub(super) fn span_of(text: &str, path: &FieldPath) -> Option<usize> {
    let mut best = None;
    let mut node = parse(text)?;
    for seg in &path.0 {
        let next = match (seg, node.kind) {
            (Seg::Key(k), Kind::Object(members)) => {
                let Some((_, span, value)) = members.into_iter().find(|(key, ..)| key == k) else {
                    break;
                };
                best = Some(span.start);
                value
            }
            (Seg::Index(i), Kind::Array(elements)) => {
                let v = elements.into_iter().nth(*i);
                best = v.as_ref().map(|v| v.start).or(best);
                v
            }
            _ => None,
        };
        match next {
            Some(n) => node = n,
            None => break,
        }
    }
    best
}

/// The byte offset of a 1-based `line` and a `column` (bytes from the line's start, as
/// serde_json counts them) in `text`.
pub(super) fn offset_of(text: &str, line: usize, column: usize) -> usize {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    (start + column).min(text.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "{\n  \"gravity\": [0, \"a\", 0],\n  \"bodies\": [\n    {\"name\": \
                        \"b\", \"shape\": {\"type\": \"ball\"}}\n  ]\n}\n";

    fn at(needle: &str) -> String {
        path_at(TEXT, TEXT.find(needle).unwrap()).to_string()
    }

    #[test]
    fn the_path_at_an_offset() {
        assert_eq!(at("\"a\""), "gravity[1]");
        assert_eq!(at("\"gravity\""), "gravity");
        assert_eq!(at("\"ball\""), "bodies[0].shape.type");
        assert_eq!(at("\"name\""), "bodies[0].name");
        assert_eq!(at("}}"), "bodies[0].shape");
        assert_eq!(path_at(TEXT, 0).to_string(), "");
        // a text cut short keeps what was read
        let cut = &TEXT[..TEXT.find("\"ball\"").unwrap() + 3];
        assert_eq!(
            path_at(cut, cut.len() - 1).to_string(),
            "bodies[0].shape.type"
        );
        // nested beyond the scanner's depth: no panic, the path as deep as it goes
        let deep = "[".repeat(100_000);
        assert_eq!(path_at(&deep, 99_999).0.len(), MAX_DEPTH);
    }

    #[test]
    fn the_offset_of_a_path() {
        let line = |p: &FieldPath| span_of(TEXT, p).map(|o| crate::scene::line_at(TEXT, o));
        let root = FieldPath::default();
        assert_eq!(line(&root.key("gravity").index(2)), Some(2));
        assert_eq!(
            line(&root.key("bodies").index(0).key("shape").key("type")),
            Some(4)
        );
        // the deepest part that exists
        assert_eq!(line(&root.key("bodies").index(3).key("mass")), Some(3));
        assert_eq!(line(&root.key("nothing")), None);
        assert_eq!(offset_of(TEXT, 2, 3), 5);
    }
}
