//! Minimal CSV reading for [`super::map`]: a header row, comma-separated fields, optional
//! double quotes (`""` inside quotes is a quote), blank lines and lines starting with `#`
//! skipped. Enough for the tables beadchain writes (sweeps, validation) and spreadsheets.

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

/// Splits one line into fields.
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur).trim().to_string()),
            (c, _) => cur.push(c),
        }
    }
    out.push(cur.trim().to_string());
    out
}

impl Table {
    /// Parses CSV text (`path` only names the file in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Table, PlotError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let header = match lines.next() {
            Some((_, l)) => fields(l),
            None => {
                return Err(PlotError::Csv {
                    path: path.to_path_buf(),
                    msg: "no header row (the file is empty)".into(),
                })
            }
        };
        let rows = lines.map(|(no, l)| (no, fields(l))).collect();
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
            "# comment\na, \"b,c\" ,d\n\n1,\"x \"\"y\"\"\",3\r\n2,,\n",
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
