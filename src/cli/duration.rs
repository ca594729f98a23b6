//! Durations on the command line (`--time-budget`, `bench --budget`, `view --exit-after`):
//! a number, scientific notation allowed, and a unit `ms`, `s` (the default), `m`/`min` or `h`.
//! Negative, NaN, infinite and values too large for a `Duration` are errors (clap names the
//! flag in front of the message).

use std::time::Duration;

/// Parse `10s`, `2m`, `500ms`, `1.5h`, `1e3s`, `2.5e-1m`, `30` (seconds).
pub fn parse_duration(s: &str) -> Result<Duration, String> {
    let s = s.trim();
    // The unit is the trailing run of letters: `1e3s` is 1e3 and `s`, `1e3` has none.
    let split = s.trim_end_matches(|c: char| c.is_ascii_alphabetic()).len();
    let (num, unit) = s.split_at(split);
    let examples = "examples: 10s, 2m, 500ms, 1.5h, 1e3s";
    let v: f64 = num
        .trim()
        .parse()
        .map_err(|_| format!("invalid duration '{s}' ({examples})"))?;
    if !v.is_finite() || v < 0.0 {
        return Err(format!(
            "invalid duration '{s}': must be a finite number ≥ 0 ({examples})"
        ));
    }
    let secs = match unit {
        "ms" => v / 1000.0,
        "s" | "" => v,
        "m" | "min" => v * 60.0,
        "h" => v * 3600.0,
        _ => {
            return Err(format!(
                "unknown time unit '{unit}' in duration '{s}' (use ms, s, m, h)"
            ));
        }
    };
    Duration::try_from_secs_f64(secs).map_err(|_| {
        format!(
            "duration '{s}' is too long (at most {} s, about 584 billion years)",
            u64::MAX
        )
    })
}

#[cfg(test)]
mod tests {
    use super::parse_duration;
    use std::time::Duration;

    #[test]
    fn units_and_scientific_notation() {
        assert_eq!(parse_duration("10s"), Ok(Duration::from_secs(10)));
        assert_eq!(parse_duration("2m"), Ok(Duration::from_secs(120)));
        assert_eq!(parse_duration("500ms"), Ok(Duration::from_millis(500)));
        assert_eq!(parse_duration("1h"), Ok(Duration::from_secs(3600)));
        assert_eq!(parse_duration("30"), Ok(Duration::from_secs(30)));
        assert_eq!(parse_duration("1e3s"), Ok(Duration::from_secs(1000)));
        assert_eq!(parse_duration("1e3"), Ok(Duration::from_secs(1000)));
        assert_eq!(parse_duration("2.5e-1m"), Ok(Duration::from_secs(15)));
        assert_eq!(parse_duration("2E1ms"), Ok(Duration::from_millis(20)));
    }

    #[test]
    fn hostile_durations_are_errors() {
        for bad in [
            "1e30s", "1e20", "-1s", "NaN", "nans", "inf", "infs", "-0.5m", "1e", "3x", "",
        ] {
            let e = parse_duration(bad).expect_err(bad);
            assert!(e.contains("duration") || e.contains("unit"), "{bad}: {e}");
        }
        assert!(parse_duration("1e30s").unwrap_err().contains("too long"));
    }
}
