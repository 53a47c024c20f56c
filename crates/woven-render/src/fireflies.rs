//! Fireflies: isolated pixels far brighter than their neighbourhood, the mark of a
//! high-variance estimator (counted on the showcase: docs/render.md).
//!
//! A pixel is a firefly when its value is above [`NEIGHBOURHOOD_FACTOR`] times the median of
//! the 5 × 5 pixels around it (itself included, clipped at the image's edges) and above the
//! image's 99th percentile.

/// How many times the neighbourhood's median a firefly exceeds.
pub const NEIGHBOURHOOD_FACTOR: f64 = 10.0;

/// The fireflies of a `width` × `height` image of `values` (row-major, e.g. luminance), as
/// `(x, y)` pixel positions. Empty for an empty image or when `values` does not hold
/// `width · height` values.
pub fn fireflies(width: usize, height: usize, values: &[f64]) -> Vec<(usize, usize)> {
    if width == 0 || height == 0 || values.len() != width * height {
        return Vec::new();
    }
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if sorted.is_empty() {
        return Vec::new();
    }
    sorted.sort_by(f64::total_cmp);
    let p99 = sorted[((sorted.len() - 1) as f64 * 0.99).round() as usize];
    let mut out = Vec::new();
    let mut window = Vec::with_capacity(25);
    for y in 0..height {
        for x in 0..width {
            let v = values[y * width + x];
            // NaN and values at or below the percentile are no fireflies.
            if v.partial_cmp(&p99) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            window.clear();
            for yy in y.saturating_sub(2)..(y + 3).min(height) {
                for xx in x.saturating_sub(2)..(x + 3).min(width) {
                    window.push(values[yy * width + xx]);
                }
            }
            window.sort_by(f64::total_cmp);
            let median = window[window.len() / 2];
            if v > NEIGHBOURHOOD_FACTOR * median {
                out.push((x, y));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_isolated_bright_pixel_is_a_firefly_and_a_bright_patch_is_not() {
        let (w, h) = (40, 30);
        let mut v = vec![0.5; w * h];
        v[10 * w + 7] = 25.0; // isolated: 50× its neighbours, above the 99th percentile (20)
        for y in 20..26 {
            for x in 30..36 {
                v[y * w + x] = 20.0; // a bright region: its neighbourhood is bright too
            }
        }
        assert_eq!(fireflies(w, h, &v), vec![(7, 10)]);
        // 9× its neighbours (and below the 99th percentile): not one.
        v[10 * w + 7] = 4.5;
        assert!(fireflies(w, h, &v).is_empty());
        // At a corner the clipped window still finds it.
        v[0] = 50.0;
        assert_eq!(fireflies(w, h, &v), vec![(0, 0)]);
    }

    #[test]
    fn malformed_input_has_none() {
        assert!(fireflies(0, 0, &[]).is_empty());
        assert!(fireflies(2, 2, &[1.0; 3]).is_empty());
        assert!(fireflies(2, 1, &[f64::NAN, f64::NAN]).is_empty());
    }
}
