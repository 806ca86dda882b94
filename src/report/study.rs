//! A study's summary tables: one row per case, as CSV (every digit) and Markdown (for
//! people: numbers to 6 significant digits), and the plot of its figure against a swept
//! key.

use super::plot::{Curve, CurvePlot};
use super::style::{self, Dash, Marker};

/// The summary of a study's cases: the header and one row of cells per case, already
/// formatted as text.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryTable {
    /// Column names, the CSV's first row; a study's are `case`, the keys its cases vary
    /// (in the study file's order), `kind`, `status`, `flags`, the metric keys (key
    /// figures first, lo before hi), `seconds` and `error`.
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
            "# Study summary\n\n{} case(s), {flagged} flagged (failed, infeasible, not verified, phi_op unstable, band clipped by the window or basis not converged).\n\n| {} | output |\n|{}\n",
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

/// The figures a study's plot shows, in order of preference: the first the rows have.
pub const PLOTTED_FIGURES: [&str; 4] = ["band_width", "band_width_after", "lowest_onset", "strict_band_width_after"];

/// The plot of a study's figure `y_key` against its swept key `x_key`: one line (with a
/// marker at every case, every other line dashed) per combination of the other keys'
/// values, named by them.
/// `series` holds each line's name and points (x, y).
pub fn sweep_plot(title: &str, x_key: &str, y_key: &str, series: Vec<(String, Vec<(f64, f64)>)>) -> CurvePlot {
    let all = || series.iter().flat_map(|s| s.1.iter().copied());
    let (x0, x1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let pad = |lo: f64, hi: f64| {
        let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
        (lo - 0.05 * span, hi + 0.05 * span)
    };
    let (y0, y1) = pad(if y0 >= 0.0 { 0.0 } else { y0 }, y1);
    let curves = series
        .into_iter()
        .enumerate()
        // Every other line dashed, so that one drawn over another stays visible.
        .map(|(k, (name, points))| Curve {
            marker: Marker::Circle,
            dash: if k % 2 == 1 { Dash::Dashed } else { Dash::Solid },
            ..Curve::new(name, style::color(k), points)
        })
        .collect();
    CurvePlot {
        title: title.to_string(),
        x_label: x_key.to_string(),
        y_label: y_key.to_string(),
        x_range: pad(x0, x1),
        y_range: (y0, y1),
        log_y: false,
        curves,
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
            "# Study summary\n\n2 case(s), 1 flagged (failed, infeasible, not verified, phi_op unstable, band clipped by the window or basis not converged).\n\n\
             | case | flags | seconds | band | output |\n|---|---|---|---|---|\n\
             | a\\|b |  | 1.23457 | 12 | [r](x) |\n| c | infeasible | 2 |  | [s](y) |\n"
        );
        assert_eq!(
            String::from_utf8(t.csv().unwrap()).unwrap(),
            "case,flags,seconds,band\na|b,,1.23456789,12\nc,infeasible,2,\n"
        );
    }
}
