//! Mutations of a robot file for the loaders' fuzz tests (`urdf_no_panic`, `mjcf_no_panic`):
//! quoted attribute values replaced.

use proptest::sample::Index;

/// The byte ranges of every quoted attribute value of `text`.
pub fn attribute_values(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let b = text.as_bytes();
    let mut i = 0;
    while i + 1 < b.len() {
        if b[i] == b'=' && b[i + 1] == b'"' {
            if let Some(len) = text[i + 2..].find('"') {
                out.push((i + 2, i + 2 + len));
                i += 2 + len;
            }
        }
        i += 1;
    }
    out
}

/// `text` with `edits` applied to its attribute values ([`attribute_values`]), one edit a
/// value (the first of several on the same one).
pub fn mutate(text: &str, edits: Vec<(Index, String)>) -> String {
    let spans = attribute_values(text);
    let mut chosen: Vec<(usize, usize, String)> = edits
        .into_iter()
        .map(|(i, v)| {
            let (a, b) = spans[i.index(spans.len())];
            (a, b, v)
        })
        .collect();
    chosen.sort_by_key(|c| std::cmp::Reverse(c.0));
    chosen.dedup_by_key(|c| c.0);
    let mut out = text.to_string();
    for (a, b, v) in chosen {
        out.replace_range(a..b, &v);
    }
    out
}
