//! The XML sanitiser run before urdf-rs parses a URDF: it removes or replaces what urdf-rs
//! refuses although real descriptions have it (`<texture/>` without a filename, an empty
//! `<geometry>`).

/// `input` with what urdf-rs refuses removed (empty textures, with a notice naming their
/// line) or replaced (empty geometries, by a zero box that rapier3d-urdf skips).
pub(super) fn sanitize(input: &str, notices: &mut Vec<String>) -> String {
    sanitize_empty_geometry(&sanitize_empty_texture(input, notices))
}

/// `<texture>` elements without a `filename` (`<texture/>`, which urdf-rs refuses; icub and
/// romeo of example-robot-data have them) are removed, with a notice naming their line.
/// Textures are never read.
fn sanitize_empty_texture(input: &str, notices: &mut Vec<String>) -> String {
    const TAG: &str = "<texture";
    let mut out = String::with_capacity(input.len());
    let mut pos = 0;
    while let Some(found) = input[pos..].find(TAG) {
        let start = pos + found;
        let after = start + TAG.len();
        let is_tag =
            input[after..].starts_with(|c: char| c.is_whitespace() || c == '/' || c == '>');
        let Some(end) = input[after..].find('>').filter(|_| is_tag) else {
            out.push_str(&input[pos..after]);
            pos = after;
            continue;
        };
        let open_end = after + end + 1;
        let open = &input[start..open_end];
        let mut stop = open_end;
        if !open.contains("filename") && !open.ends_with("/>") {
            // <texture ...> ... </texture>
            match input[open_end..].find("</texture>") {
                Some(close) => stop = open_end + close + "</texture>".len(),
                None => stop = start,
            }
        }
        if open.contains("filename") || stop == start {
            out.push_str(&input[pos..open_end]);
            pos = open_end;
            continue;
        }
        notices.push(format!(
            "line {}: <texture> without a filename ignored (textures are not read)",
            crate::scene::line_at(input, start)
        ));
        out.push_str(&input[pos..start]);
        pos = stop;
    }
    out.push_str(&input[pos..]);
    out
}

/// `<geometry></geometry>` with nothing inside (which urdf-rs rejects) → a zero box, which
/// rapier3d-urdf skips (the same sanitising `rapier3d-urdf` does on its own entry points).
fn sanitize_empty_geometry(input: &str) -> String {
    let mut out = String::with_capacity(input.len());
    let mut rem = input;
    while let Some(start) = rem.find("<geometry") {
        let (before, tag) = rem.split_at(start);
        out.push_str(before);
        let Some(end) = tag.find('>') else {
            out.push_str(tag);
            return out;
        };
        let open = &tag[..=end];
        out.push_str(open);
        let body = &tag[end + 1..];
        if open.ends_with("/>") {
            rem = body;
            continue;
        }
        match body.find("</geometry>") {
            Some(close) if body[..close].trim().is_empty() => {
                out.push_str("<box size=\"0 0 0\"/>");
                rem = &body[close..];
            }
            _ => rem = body,
        }
    }
    out.push_str(rem);
    out
}
