//! Numbers as messages show them, for every layer (a value in an error of the linear
//! algebra, the model or the problem file prints the same way), rounded to the digits
//! that mean something in text and titles, and speeds in the unit the user gave them.

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

/// rad/s per revolution per minute: 2π rad per revolution, 60 s per minute (π/30).
pub const RAD_PER_S_PER_RPM: f64 = std::f64::consts::PI / 30.0;

/// `x` rounded to `digits` significant digits, in the shortest form that reads back to
/// the rounded value: `sig(1256.6370614359173, 5)` is `1256.6`, `sig(12000.000000000002,
/// 6)` is `12000`, `sig(2.8e-4, 3)` is `0.00028`. What text and titles print; machine
/// files (JSON, tuned.toml) keep full precision.
pub fn sig(x: f64, digits: usize) -> String {
    if !x.is_finite() || x == 0.0 {
        return number(if x == 0.0 { 0.0 } else { x });
    }
    let rounded: f64 = format!("{x:.*e}", digits.saturating_sub(1)).parse().unwrap_or(x);
    number(rounded)
}

/// The unit a speed is shown in: rad/s, or rpm (with rad/s beside it) when the user gave
/// the speed in rpm (`speed_rpm` in the file, `--speeds …rpm`). Computations are in rad/s
/// throughout; this is display only.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum SpeedUnit {
    /// rad/s.
    #[default]
    RadPerS,
    /// rpm, with rad/s beside it in text.
    Rpm,
}

impl SpeedUnit {
    /// `Rpm` when `rpm` is true.
    pub fn of(rpm: bool) -> SpeedUnit {
        if rpm {
            SpeedUnit::Rpm
        } else {
            SpeedUnit::RadPerS
        }
    }

    /// A speed Ω (rad/s) for text and titles: `1256.6 rad/s`, or `12000 rpm (1256.6 rad/s)`.
    pub fn text(self, speed: f64) -> String {
        match self {
            SpeedUnit::RadPerS => format!("{} rad/s", sig(speed, 5)),
            SpeedUnit::Rpm => format!("{} rpm ({} rad/s)", sig(speed / RAD_PER_S_PER_RPM, 5), sig(speed, 5)),
        }
    }

    /// A speed range for text: `837.76 to 1466.1 rad/s`, or `8000 to 14000 rpm (837.76 to
    /// 1466.1 rad/s)`.
    pub fn range(self, lo: f64, hi: f64) -> String {
        match self {
            SpeedUnit::RadPerS => format!("{} to {} rad/s", sig(lo, 5), sig(hi, 5)),
            SpeedUnit::Rpm => format!(
                "{} to {} rpm ({} to {} rad/s)",
                sig(lo / RAD_PER_S_PER_RPM, 5),
                sig(hi / RAD_PER_S_PER_RPM, 5),
                sig(lo, 5),
                sig(hi, 5)
            ),
        }
    }

    /// The value of Ω (rad/s) on an axis in this unit.
    pub fn value(self, speed: f64) -> f64 {
        match self {
            SpeedUnit::RadPerS => speed,
            SpeedUnit::Rpm => speed / RAD_PER_S_PER_RPM,
        }
    }

    /// The unit's name on an axis: `rad/s` or `rpm`.
    pub fn unit(self) -> &'static str {
        match self {
            SpeedUnit::RadPerS => "rad/s",
            SpeedUnit::Rpm => "rpm",
        }
    }

    /// The speed's symbol on an axis: Ω (rad/s) or n (rpm).
    pub fn symbol(self) -> &'static str {
        match self {
            SpeedUnit::RadPerS => "Ω",
            SpeedUnit::Rpm => "n",
        }
    }
}

/// A value that may be +∞ in JSON, which has no infinity: a non-finite value is written
/// `null` and `null` reads back as +∞. For numbers such as a penalised cost in a design's
/// history (`exp` of a penalty overflows) or the β = 0 deviation of a monodromy without
/// finite multipliers.
pub mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    /// A finite value as the number, a non-finite one as `null`.
    pub fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
        if value.is_finite() {
            serializer.serialize_f64(*value)
        } else {
            serializer.serialize_none()
        }
    }

    /// A number as itself, `null` as +∞.
    pub fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::INFINITY))
    }
}

#[cfg(test)]
mod tests {
    use super::{number, sig, SpeedUnit};

    #[test]
    fn significant_digits_and_speeds() {
        assert_eq!(sig(1256.6370614359173, 5), "1256.6");
        assert_eq!(sig(12000.000000000002, 6), "12000");
        assert_eq!(sig(837.7580409572781, 5), "837.76");
        assert_eq!(sig(2.8e-4, 3), "0.00028");
        assert_eq!(sig(1.8747e-3, 3), "0.00187");
        assert_eq!(sig(0.0, 3), "0");
        assert_eq!(SpeedUnit::Rpm.text(1256.6370614359173), "12000 rpm (1256.6 rad/s)");
        assert_eq!(SpeedUnit::RadPerS.text(2000.0), "2000 rad/s");
        assert_eq!(
            SpeedUnit::Rpm.range(837.7580409572781, 1466.0765716752367),
            "8000 to 14000 rpm (837.76 to 1466.1 rad/s)"
        );
    }

    #[test]
    fn huge_and_tiny_values_print_in_exponent_form() {
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-2.5e-9), "-2.5e-9");
        assert_eq!(number(1230.5), "1230.5");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::INFINITY), "inf");
    }
}
