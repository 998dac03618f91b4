//! CSV tables for [`super::map`], read by the `csv` crate (RFC 4180: a header row, fields
//! optionally in double quotes, `""` inside quotes is a quote), fields trimmed, blank lines and
//! lines starting with `#` skipped: the tables beadchain writes (sweeps, validation) and
//! spreadsheets'.

use super::PlotError;
use std::path::Path;

/// A CSV file: header and rows (each with its 1-based line number).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Column names (trimmed).
    pub header: Vec<String>,
    /// `(line number, fields)`.
    pub rows: Vec<(usize, Vec<String>)>,
}

/// The 1-based line of a record the reader places at byte `start`: the reader's position is
/// where it began looking (blank and comment lines before the record included), and its own
/// line count skips comments, so the line is found from the text.
fn first_line(text: &str, start: usize) -> usize {
    let before = &text[..start.min(text.len())];
    let mut line = 1 + before.bytes().filter(|&b| b == b'\n').count();
    for l in text[before.len()..].split('\n') {
        let t = l.trim();
        if !t.is_empty() && !t.starts_with('#') {
            break;
        }
        line += 1;
    }
    line
}

impl Table {
    /// Parses CSV text (`path` only names the file in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Table, PlotError> {
        let err = |msg: String| PlotError::Csv {
            path: path.to_path_buf(),
            msg,
        };
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let mut rows = Vec::new();
        for record in reader.records() {
            let record = record.map_err(|e| err(e.to_string()))?;
            let line = first_line(text, record.position().map_or(0, |p| p.byte() as usize));
            let fields: Vec<String> = record.iter().map(String::from).collect();
            // a line of blanks only is a blank line
            if !(fields.len() == 1 && fields[0].is_empty()) {
                rows.push((line, fields));
            }
        }
        if rows.is_empty() {
            return Err(err("no header row (the file is empty)".into()));
        }
        let (_, header) = rows.remove(0);
        Ok(Table { header, rows })
    }

    /// Reads and parses `path`.
    pub fn read(path: &Path) -> Result<Table, PlotError> {
        let text = crate::files::read_text(path).map_err(|e| PlotError::Csv {
            path: path.to_path_buf(),
            msg: format!("cannot read: {e}"),
        })?;
        Table::parse(&text, path)
    }

    /// Index of column `name`; a missing column is an error naming it, the file and the
    /// columns there are.
    pub fn column(&self, name: &str, path: &Path) -> Result<usize, PlotError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| PlotError::Csv {
                path: path.to_path_buf(),
                msg: format!("no column `{name}` (columns: {})", self.header.join(", ")),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_blank_and_comment_lines() {
        let t = Table::parse(
            "# comment\na,\"b,c\" ,d\n\n1,\"x \"\"y\"\"\",3\r\n2,,\n",
            Path::new("t.csv"),
        )
        .unwrap();
        assert_eq!(t.header, vec!["a", "b,c", "d"]);
        assert_eq!(
            t.rows[0],
            (4, vec!["1".into(), "x \"y\"".into(), "3".into()])
        );
        assert_eq!(
            t.rows[1],
            (5, vec!["2".into(), String::new(), String::new()])
        );
        let e = t.column("z", Path::new("t.csv")).unwrap_err().to_string();
        assert!(e.contains("t.csv") && e.contains("`z`"), "{e}");
        assert!(Table::parse("\n", Path::new("e.csv")).is_err());
    }
}
