//! Parsing of command-line values.

use crate::Error;

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
            let n = ((b - a) / step + 1e-9).floor() + 1.0;
            if n > MAX_RANGE_POINTS as f64 {
                return Err(bad(format!("`{text}` expands to {n} points, more than {MAX_RANGE_POINTS}")));
            }
            Ok((0..n as usize).map(|i| a + i as f64 * step).collect())
        }
        _ => Err(bad(format!("`{text}` is not of the form A:B:STEP"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
