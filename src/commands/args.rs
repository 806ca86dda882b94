//! Parsing of command-line values.

use crate::commands::Error;

/// Most points a range may expand to: protects against `0:1e9:1e-9` exhausting memory.
pub const MAX_RANGE_POINTS: usize = 10_000_000;

/// Parse `A:B:STEP` (or a single value `A`) into A, A+STEP, …, up to B inclusive.
/// The count is rounded so that floating-point drift neither drops nor adds the end point.
pub fn parse_range(text: &str, argument: &str) -> Result<Vec<f64>, Error> {
    let bad = |message: String| Error::Argument { argument: argument.into(), message };
    let parts: Vec<&str> = text.split(':').collect();
    let nums = parts
        .iter()
        .map(|p| {
            p.trim().parse::<f64>().map_err(|_| bad(format!("`{p}` in `{text}` is not a number (expected A:B:STEP)")))
        })
        .collect::<Result<Vec<f64>, Error>>()?;
    if nums.iter().any(|x| !x.is_finite()) {
        return Err(bad(format!("`{text}` has a non-finite number")));
    }
    match nums.as_slice() {
        [a] => Ok(vec![*a]),
        [a, b, step] => {
            if *step <= 0.0 || b < a {
                return Err(bad(format!("`{text}` needs A <= B and STEP > 0")));
            }
            let grid = rotorshunt::analysis::Interval::new(*a, *b);
            grid.stepped(*step, MAX_RANGE_POINTS).ok_or_else(|| {
                bad(format!(
                    "`{text}` expands to {} points, more than {MAX_RANGE_POINTS}",
                    rotorshunt::analysis::limits::number(grid.step_count(*step))
                ))
            })
        }
        _ => Err(bad(format!("`{text}` is not of the form A:B:STEP"))),
    }
}

/// Parse a range of rotating speeds: `A:B:STEP` in rad/s, or in rpm with the suffix
/// `rpm` (`0:30000:500rpm`, `3000 rpm`), each point then converted, Ω = n·π/30 rad/s
/// ([`rotorshunt::problem::units::RAD_PER_S_PER_RPM`]); `rad/s` may be written out. Returns
/// the speeds (rad/s) and the unit the range was given in (rpm with the suffix), for
/// echoing the speeds back in it.
pub fn parse_speeds(text: &str, argument: &str) -> Result<(Vec<f64>, rotorshunt::numbers::SpeedUnit), Error> {
    let unit = rotorshunt::numbers::SpeedUnit::of(text.trim().to_ascii_lowercase().ends_with("rpm"));
    Ok((parse_speed_range_in(text, argument)?, unit))
}

fn parse_speed_range_in(text: &str, argument: &str) -> Result<Vec<f64>, Error> {
    let t = text.trim();
    let lower = t.to_ascii_lowercase();
    if let Some(n) = lower.strip_suffix("rpm") {
        let rpm = parse_range(&t[..n.len()], argument)?;
        return Ok(rpm.into_iter().map(|n| n * rotorshunt::problem::units::RAD_PER_S_PER_RPM).collect());
    }
    match lower.strip_suffix("rad/s") {
        Some(n) => parse_range(&t[..n.len()], argument),
        None => parse_range(t, argument),
    }
}

/// Split a comma-separated flag value (`--nodes 3,16`, `--modes f1,fr1`) into its trimmed
/// entries: a blank text is no entry, and an empty entry (`3,,4`, `,`, a trailing comma) is
/// refused naming the flag, rather than skipped.
pub fn parse_list<'a>(text: &'a str, argument: &str) -> Result<Vec<&'a str>, Error> {
    if text.trim().is_empty() {
        return Ok(Vec::new());
    }
    let entries: Vec<&str> = text.split(',').map(str::trim).collect();
    match entries.iter().position(|e| e.is_empty()) {
        Some(i) => Err(Error::Argument {
            argument: argument.into(),
            message: format!(
                "entry {} of `{text}` is empty: give entries separated by single commas, e.g. `a,b`",
                i + 1
            ),
        }),
        None => Ok(entries),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_refuse_empty_entries() {
        assert_eq!(parse_list("", "x").unwrap(), Vec::<&str>::new());
        assert_eq!(parse_list("  ", "x").unwrap(), Vec::<&str>::new());
        assert_eq!(parse_list(" 3, 16 ", "x").unwrap(), vec!["3", "16"]);
        for bad in ["3,,4", ",", "3,", ",3", "3, ,4"] {
            let e = parse_list(bad, "--nodes").unwrap_err().to_string();
            assert!(e.starts_with("argument `--nodes`: entry "), "{bad}: {e}");
        }
    }

    fn parse_speed_range(text: &str, argument: &str) -> Result<Vec<f64>, Error> {
        parse_speeds(text, argument).map(|(speeds, _)| speeds)
    }

    #[test]
    fn speed_ranges_in_rpm_are_converted_point_by_point() {
        assert_eq!(parse_speeds("0:300:100rpm", "x").unwrap().1, rotorshunt::numbers::SpeedUnit::Rpm);
        assert_eq!(parse_speeds("0:300:100", "x").unwrap().1, rotorshunt::numbers::SpeedUnit::RadPerS);
        let rad = parse_speed_range("0:3000:100", "x").unwrap();
        assert_eq!(parse_speed_range("0:3000:100 rad/s", "x").unwrap(), rad);
        let rpm = parse_speed_range("0:30000:1000rpm", "x").unwrap();
        assert_eq!(rpm.len(), 31);
        let pi_30 = std::f64::consts::PI / 30.0;
        for (k, w) in rpm.iter().enumerate() {
            assert_eq!(*w, (k as f64 * 1000.0) * pi_30);
        }
        assert_eq!(parse_speed_range("19099 RPM", "x").unwrap(), vec![19099.0 * pi_30]);
        assert!(parse_speed_range("rpm", "x").is_err());
        assert!(parse_speed_range("1:0:1 rpm", "x").is_err());
    }

    #[test]
    fn ranges() {
        assert_eq!(parse_range("0:3000:100", "x").unwrap().len(), 31);
        assert_eq!(parse_range("100:14000:25", "x").unwrap().len(), 557);
        assert_eq!(parse_range("0:1:0.025", "x").unwrap().len(), 41);
        assert_eq!(parse_range("5", "x").unwrap(), vec![5.0]);
        assert!(parse_range("1:0:1", "x").is_err());
        assert!(parse_range("0:1:0", "x").is_err());
        assert!(parse_range("a:b", "x").is_err());
        assert!(parse_range("0:1e12:1e-6", "x").is_err());
    }
}
