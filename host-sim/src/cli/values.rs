//! clap value parsers for the numbers of the command line: each refuses what it cannot take
//! (not a number, NaN, infinite, negative, out of range) with the value and what is allowed,
//! before any work. Numeric options that can be typed negative take `allow_hyphen_values`, so
//! that `--loss -0.1` reaches these parsers instead of clap's `unexpected argument '-0'`.
//!
//! clap's own typed parsers (`value_parser!(u64).range(..)`) say `invalid digit found in
//! string` for `-1`; these say `-1 is not allowed: a whole number from 0 to …`.

/// A parser of finite numbers from `lo` to `hi` (`what` names them in the message: `a
/// probability`, `a number of seconds`).
pub fn number(
    lo: f64,
    hi: f64,
    what: &'static str,
) -> impl Fn(&str) -> Result<f64, String> + Clone {
    move |s: &str| {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("{s:?} is not a number; {what} from {lo} to {hi} is allowed"))?;
        if !v.is_finite() {
            return Err(format!(
                "{s} is not a finite number; {what} from {lo} to {hi} is allowed"
            ));
        }
        if !(lo..=hi).contains(&v) {
            return Err(format!(
                "{s} is out of range; {what} from {lo} to {hi} is allowed"
            ));
        }
        Ok(v)
    }
}

/// A parser of finite numbers greater than 0 and at most `hi`.
pub fn positive(hi: f64, what: &'static str) -> impl Fn(&str) -> Result<f64, String> + Clone {
    move |s: &str| {
        let v = number(f64::MIN, hi, what)(s).map_err(|_| {
            format!("{s} is not allowed; {what}, greater than 0 and at most {hi}, is allowed")
        })?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!(
                "{s} is not allowed; {what}, greater than 0 and at most {hi}, is allowed"
            ))
        }
    }
}

/// A parser of whole numbers from `lo` to `hi`, as `T`.
pub fn whole<T>(lo: u64, hi: u64) -> impl Fn(&str) -> Result<T, String> + Clone
where
    T: TryFrom<u64>,
{
    move |s: &str| {
        let allowed = format!("a whole number from {lo} to {hi} is allowed");
        let v: i128 = s
            .trim()
            .parse()
            .map_err(|_| format!("{s:?} is not a whole number; {allowed}"))?;
        u64::try_from(v)
            .ok()
            .filter(|v| (lo..=hi).contains(v))
            .and_then(|v| T::try_from(v).ok())
            .ok_or_else(|| format!("{s} is out of range; {allowed}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_parser_names_the_value_and_what_is_allowed() {
        let p = number(0.0, 1.0, "a probability");
        assert_eq!(p("0.25"), Ok(0.25));
        assert_eq!(
            p("-0.1").unwrap_err(),
            "-0.1 is out of range; a probability from 0 to 1 is allowed"
        );
        assert!(
            p("nan")
                .unwrap_err()
                .starts_with("nan is not a finite number")
        );
        assert!(
            p("inf")
                .unwrap_err()
                .starts_with("inf is not a finite number")
        );
        assert!(p("x").unwrap_err().starts_with("\"x\" is not a number"));
        let r = positive(1e6, "a number of metres");
        assert_eq!(r("1.5"), Ok(1.5));
        assert!(r("0").is_err() && r("-1").is_err() && r("1e300").is_err());
        let w = whole::<u16>(1, 1000);
        assert_eq!(w("7"), Ok(7));
        assert_eq!(
            w("-1").unwrap_err(),
            "-1 is out of range; a whole number from 1 to 1000 is allowed"
        );
        assert!(w("1.5").unwrap_err().contains("not a whole number"));
        assert_eq!(
            whole::<u64>(0, u64::MAX)("18446744073709551615"),
            Ok(u64::MAX)
        );
    }
}
