//! The elements that mjcf-rs does not read: `<deformable>` (flexes, skins), and in the body
//! tree `<replicate>` (MuJoCo 3),
//! `<composite>` and `<flexcomp>` anywhere, an `<attach>` inside a `<frame>`, and an
//! `<attach>` whose sub-model mjcf-rs could not load or that names no body of it. mjcf-rs
//! drops each without a word (a log line at most): the bodies, joints and geoms they carry or
//! generate were missing from the robot, and a run went on without them. A notice names each,
//! its line (and its file, in an `<include>`d file) and what is not loaded. They are notices,
//! not errors: what is dropped is a whole subtree hanging below the rest, which loads as
//! written (nothing else of the tree is placed relative to it).

use super::check::element_at;
use rapier3d_mjcf::mjcf_rs::model::Model;
use std::path::Path;

/// The tags mjcf-rs skips wherever they are in the body tree.
const GENERATORS: &[&str] = &["replicate", "composite", "flexcomp"];

/// A notice for each element of the body tree that mjcf-rs drops, in the model's own text
/// `doc` (read from `base`) and in the `included` files (path, text), see the module's doc.
pub(super) fn notices(
    doc: Option<&roxmltree::Document>,
    base: &Path,
    included: &[(String, String)],
) -> Vec<String> {
    let docs: Vec<(String, roxmltree::Document)> = included
        .iter()
        .filter_map(|(f, t)| Some((format!("`{f}`: "), roxmltree::Document::parse(t).ok()?)))
        .collect();
    let bases: Vec<&Path> = included
        .iter()
        .map(|(f, _)| Path::new(f).parent().unwrap_or(Path::new("")))
        .collect();
    let all = doc.map(|d| ("", d, base)).into_iter().chain(
        docs.iter()
            .zip(&bases)
            .map(|((at, d), b)| (at.as_str(), d, *b)),
    );
    // the `<asset><model>`s of all the files, as mjcf-rs registers them (name, file, base)
    let all: Vec<_> = all.collect();
    let sub_models: Vec<(&str, &str, &Path)> = all
        .iter()
        .flat_map(|(_, d, b)| {
            d.root_element()
                .children()
                .filter(|n| n.has_tag_name("asset"))
                .flat_map(|a| a.children().filter(|n| n.has_tag_name("model")))
                .filter_map(|m| Some((m.attribute("name")?, m.attribute("file")?, *b)))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut notices = Vec::new();
    for (at, d, _) in &all {
        // `<deformable>` (MuJoCo's flexes and skins): mjcf-rs reads none of it
        for de in d
            .root_element()
            .children()
            .filter(|n| n.has_tag_name("deformable"))
        {
            let parts: Vec<String> = de
                .children()
                .filter(|n| n.is_element())
                .map(|n| element_at(d, &n))
                .collect();
            if !parts.is_empty() {
                notices.push(format!(
                    "{at}{}: not loaded (no flex or skin in rapier): {}",
                    element_at(d, &de),
                    parts.join(", ")
                ));
            }
        }
        for wb in d
            .root_element()
            .descendants()
            .filter(|n| n.has_tag_name("worldbody"))
        {
            walk(d, wb, at, &sub_models, &mut notices);
        }
    }
    notices
}

/// The notices of the elements below `node` of `doc` (`at` names its file).
fn walk(
    doc: &roxmltree::Document,
    node: roxmltree::Node,
    at: &str,
    sub_models: &[(&str, &str, &Path)],
    notices: &mut Vec<String>,
) {
    for child in node.children().filter(|n| n.is_element()) {
        let tag = child.tag_name().name();
        let el = element_at(doc, &child);
        if tag == "replicate" {
            let copies: Option<usize> =
                child.attribute("count").and_then(|c| c.trim().parse().ok());
            let (b, j, g, more) = carried(child);
            let what = format!(
                "{b} body(ies), {j} joint(s) and {g} geom(s){}",
                if more {
                    " and what its own generators make"
                } else {
                    ""
                }
            );
            let what = match copies {
                Some(n) => format!("its {n} copies of {what}"),
                None => format!("its copies of {what}"),
            };
            notices.push(format!(
                "{at}{el}: not read by mjcf-rs (the MJCF parser; MuJoCo 3's <replicate>): {what} \
                 are not loaded"
            ));
        } else if GENERATORS.contains(&tag) {
            notices.push(format!(
                "{at}{el}: not read by mjcf-rs (the MJCF parser): the bodies, joints and geoms \
                 it generates are not loaded"
            ));
        } else if tag == "attach" {
            let model = child.attribute("model").unwrap_or("");
            let body = child.attribute("body").unwrap_or("");
            let what = format!(
                "body `{body}` of model `{model}` and what hangs on it (bodies, joints, geoms) \
                 are not loaded"
            );
            if node.has_tag_name("frame") {
                notices.push(format!(
                    "{at}{el}: not read by mjcf-rs (the MJCF parser) inside a <frame>: {what}"
                ));
            } else if let Some(why) = unattachable(model, body, sub_models) {
                notices.push(format!("{at}{el}: {why}: {what}"));
            }
        } else {
            walk(doc, child, at, sub_models, notices);
        }
    }
}

/// The bodies, joints and geoms written below `node` (those of a nested `<replicate>` times
/// its count), and whether something below generates more (a `<composite>`, `<flexcomp>` or
/// `<attach>`).
fn carried(node: roxmltree::Node) -> (usize, usize, usize, bool) {
    let (mut b, mut j, mut g, mut more) = (0, 0, 0, false);
    for child in node.children().filter(|n| n.is_element()) {
        match child.tag_name().name() {
            "body" => b += 1,
            "joint" | "freejoint" => j += 1,
            "geom" => g += 1,
            "composite" | "flexcomp" | "attach" => {
                more = true;
                continue;
            }
            _ => {}
        }
        let (cb, cj, cg, cm) = carried(child);
        let n = match child.tag_name().name() {
            "replicate" => child
                .attribute("count")
                .and_then(|c| c.trim().parse().ok())
                .unwrap_or(1),
            _ => 1,
        };
        (b, j, g, more) = (b + n * cb, j + n * cj, g + n * cg, more || cm);
    }
    (b, j, g, more)
}

/// Why mjcf-rs skips an `<attach model body>` outside a frame (it only logs): no
/// `<asset><model>` of that name, a sub-model it cannot read, or no body of that name in it.
/// `None` when it attaches.
fn unattachable(model: &str, body: &str, sub_models: &[(&str, &str, &Path)]) -> Option<String> {
    let Some((_, file, base)) = sub_models.iter().rev().find(|(n, _, _)| *n == model) else {
        return Some(format!(
            "no <asset><model name=\"{model}\"> declares its model"
        ));
    };
    let path = base.join(file);
    // (read through the input cap, as the model's own files are)
    let text = match crate::io::read_input_text(&path) {
        Ok(t) => t,
        Err(e) => {
            return Some(format!(
                "model `{model}`: file `{}` {}",
                path.display(),
                e.kind.reason()
            ))
        }
    };
    let sub_base = path.parent().unwrap_or(Path::new(""));
    match Model::from_str(&text, sub_base) {
        Err(e) => Some(format!(
            "model `{model}`: file `{}` not read by mjcf-rs: {e}",
            path.display()
        )),
        Ok(sub)
            if !sub
                .bodies
                .iter()
                .skip(1)
                .any(|b| b.body.name.as_deref() == Some(body)) =>
        {
            Some(format!(
                "model `{model}` (file `{}`) has no body `{body}`",
                path.display()
            ))
        }
        Ok(_) => None,
    }
}
