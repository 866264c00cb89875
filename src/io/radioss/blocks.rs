//! Splitting a deck's text into keyword blocks: a block starts at a line beginning with `/`
//! and runs until the next one; comments (`#`, `$`) are dropped, `/END` and `#ENDDATA` end
//! the data, and `#include` is not followed (a notice says so).

use super::fields::Line;
use super::Notice;

/// One keyword block with its non-comment lines.
pub(super) struct Block<'a> {
    /// Line of the keyword.
    pub(super) line: usize,
    /// The keyword line as written.
    pub(super) header: &'a str,
    /// Keyword parts after the leading `/`, trimmed (`["PROP", "TYPE45", "2", "2"]`).
    pub(super) parts: Vec<&'a str>,
    /// Non-comment lines of the block.
    pub(super) body: Vec<Line<'a>>,
}

impl Block<'_> {
    /// Keyword part `i` in upper case (empty if absent).
    pub(super) fn part(&self, i: usize) -> String {
        self.parts
            .get(i)
            .map(|s| s.to_ascii_uppercase())
            .unwrap_or_default()
    }

    /// The block's name for messages: its keyword line without trailing blanks.
    pub(super) fn name(&self) -> String {
        self.header.trim_end().to_string()
    }
}

fn starts_with_ci(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len())
        .is_some_and(|s| s.eq_ignore_ascii_case(prefix))
}

/// The blocks of `text` (from file `file`), in file order; remarks go to `notices`.
pub(super) fn split_blocks<'a>(
    text: &'a str,
    file: &str,
    notices: &mut Vec<Notice>,
) -> Vec<Block<'a>> {
    let mut blocks: Vec<Block<'a>> = Vec::new();
    for (i, text) in text.lines().enumerate() {
        let no = i + 1;
        if starts_with_ci(text, "#ENDDATA") {
            break;
        }
        if text.starts_with('#') || text.starts_with('$') {
            if starts_with_ci(text, "#include") {
                let message = "#include is not followed: the included file is not read";
                notices.push(Notice::new(file, no, message));
            }
            continue;
        }
        if let Some(rest) = text.strip_prefix('/') {
            let parts: Vec<&str> = rest.trim_end().split('/').map(str::trim).collect();
            if parts.len() == 1 && parts[0].eq_ignore_ascii_case("END") {
                break;
            }
            blocks.push(Block {
                line: no,
                header: text,
                parts,
                body: Vec::new(),
            });
            continue;
        }
        match blocks.last_mut() {
            Some(b) => b.body.push(Line { no, text }),
            None if !text.trim().is_empty() => {
                notices.push(Notice::new(file, no, "line outside any block ignored"));
            }
            None => {}
        }
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_comments_and_end() {
        let text = "stray\n/PROP/TYPE45/2\n# c\ntitle\n#include x\n/FUNCT/1\nf\n/END\n/UNIT/1\n";
        let mut notices = Vec::new();
        let blocks = split_blocks(text, "t.rad", &mut notices);
        assert_eq!(blocks.len(), 2);
        assert_eq!(blocks[0].parts, ["PROP", "TYPE45", "2"]);
        assert_eq!(blocks[0].body.len(), 1);
        assert_eq!(blocks[1].name(), "/FUNCT/1");
        let lines: Vec<usize> = notices.iter().map(|n| n.line).collect();
        assert_eq!(lines, [1, 5]);
    }
}
