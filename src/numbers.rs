//! Numbers as messages show them, for every layer (a value in an error of the linear
//! algebra, the model or the problem file prints the same way).

/// A value as messages show it: in full, except beyond 10¹⁵ or below 10⁻⁶ in magnitude,
/// where the exponent form keeps 1e300 from printing as 301 digits.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-6..1e15).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn huge_and_tiny_values_print_in_exponent_form() {
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-2.5e-9), "-2.5e-9");
        assert_eq!(number(1230.5), "1230.5");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::INFINITY), "inf");
    }
}
