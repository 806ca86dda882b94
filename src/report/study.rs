//! A study's summary tables: one row per case, as CSV (every digit) and Markdown (for
//! people: numbers to 6 significant digits).

/// The summary of a study's cases: the header and one row of cells per case, already
/// formatted as text.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryTable {
    /// Column names, the CSV's first row; a study's are `case`, `kind`, `status`, `flags`,
    /// `seconds`, the metric keys (sorted) and `error`.
    pub header: Vec<String>,
    /// One row per case, as many cells as the header.
    pub rows: Vec<Vec<String>>,
}

impl SummaryTable {
    /// The table as CSV (RFC 4180 quoting).
    pub fn csv(&self) -> Result<Vec<u8>, csv::Error> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(&self.header)?;
        for r in &self.rows {
            w.write_record(r)?;
        }
        w.into_inner().map_err(|e| e.into_error().into())
    }

    /// The table as a Markdown page under the heading "Study summary", with a last
    /// column `output` holding `links[i]` (Markdown link text) for row i, and the count of
    /// flagged rows (column `flags`) above the table.
    pub fn markdown(&self, links: &[String]) -> String {
        let flagged = match self.header.iter().position(|h| h == "flags") {
            Some(i) => self.rows.iter().filter(|r| r.get(i).is_some_and(|c| !c.is_empty())).count(),
            None => 0,
        };
        let mut md = format!(
            "# Study summary\n\n{} case(s), {flagged} flagged (failed, infeasible, not verified or phi_op unstable).\n\n| {} | output |\n|{}\n",
            self.rows.len(),
            self.header.join(" | "),
            "---|".repeat(self.header.len() + 1)
        );
        for (i, r) in self.rows.iter().enumerate() {
            let link = links.get(i).map_or("", String::as_str);
            md += &format!("| {} | {link} |\n", r.iter().map(|c| short(c)).collect::<Vec<_>>().join(" | "));
        }
        md
    }
}

/// A cell for Markdown: a decimal number to 6 significant digits, other text with `|`
/// escaped.
fn short(c: &str) -> String {
    match c.parse::<f64>() {
        Ok(x) if c.contains('.') || c.contains('e') => format!("{}", format!("{x:.5e}").parse::<f64>().unwrap_or(x)),
        _ => c.replace('|', "\\|"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_rounds_numbers_escapes_bars_counts_flags_and_links() {
        let t = SummaryTable {
            header: vec!["case".into(), "flags".into(), "seconds".into(), "band".into()],
            rows: vec![
                vec!["a|b".into(), "".into(), "1.23456789".into(), "12".into()],
                vec!["c".into(), "infeasible".into(), "2".into(), "".into()],
            ],
        };
        assert_eq!(
            t.markdown(&["[r](x)".into(), "[s](y)".into()]),
            "# Study summary\n\n2 case(s), 1 flagged (failed, infeasible, not verified or phi_op unstable).\n\n\
             | case | flags | seconds | band | output |\n|---|---|---|---|---|\n\
             | a\\|b |  | 1.23457 | 12 | [r](x) |\n| c | infeasible | 2 |  | [s](y) |\n"
        );
        assert_eq!(
            String::from_utf8(t.csv().unwrap()).unwrap(),
            "case,flags,seconds,band\na|b,,1.23456789,12\nc,infeasible,2,\n"
        );
    }
}
