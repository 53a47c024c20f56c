//! Numbers for people, in the commands' summaries: thousands separators, percentages, file sizes
//! and durations. (Numbers in output files are [`crate::io::push_f64`]'s; axis labels are
//! [`crate::plotting::tick_label`]'s.)

use std::time::Duration;

/// `n` with thousands separated by commas: `2,558,430`.
pub fn group_digits(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A fraction as a percentage with two significant digits: `0.0402` → `4.0 %`.
pub fn percent(x: f64) -> String {
    let p = 100.0 * x;
    let decimals = match p.abs() {
        a if a >= 10.0 => 0,
        a if a >= 1.0 => 1,
        a if a >= 0.1 => 2,
        _ => 3,
    };
    format!("{p:.decimals$} %")
}

/// A file size in megabytes (10⁶ bytes), or kilobytes below one megabyte.
pub fn megabytes(bytes: u64) -> String {
    if bytes >= 1_000_000 {
        format!("{:.1} MB", bytes as f64 / 1e6)
    } else {
        format!("{:.1} kB", bytes as f64 / 1e3)
    }
}

/// A duration in seconds (milliseconds below a tenth of a second), with a sensible number of
/// digits.
pub fn seconds(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 0.1 {
        format!("{:.0} ms", 1e3 * s)
    } else if s < 10.0 {
        format!("{s:.2} s")
    } else {
        format!("{s:.1} s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_for_people() {
        assert_eq!(group_digits(2_558_430), "2,558,430");
        assert_eq!(group_digits(999), "999");
        assert_eq!(group_digits(1000), "1,000");
        assert_eq!(megabytes(10_340_000), "10.3 MB");
        assert_eq!(megabytes(52_000), "52.0 kB");
        assert_eq!(seconds(Duration::from_millis(1234)), "1.23 s");
        assert_eq!(seconds(Duration::from_micros(4400)), "4 ms");
        assert_eq!(percent(0.04021), "4.0 %");
        assert_eq!(percent(0.2316), "23 %");
        assert_eq!(percent(0.00134), "0.13 %");
        assert_eq!(percent(0.0004), "0.040 %");
        assert_eq!(seconds(Duration::from_secs(75)), "75.0 s");
    }
}
