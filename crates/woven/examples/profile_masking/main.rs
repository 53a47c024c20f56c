//! Draws `docs/img/profile-masking.svg` (docs/masking.md): three periods of an arc-topped yarn
//! profile under grazing light, the lit intervals of `Profile::lit` in orange, the ray-casting
//! verdict as dots beside the profile (filled = lit), the neighbour's silhouette point and the
//! shadow line it casts. Not shown in the README (a figure for the docs, not an API example).
//!
//! `cargo run -p woven --example profile_masking -- docs/img/profile-masking.svg` (without an
//! argument it writes `profile-masking.svg` in the system's temporary folder).

use std::fmt::Write as _;
use std::path::PathBuf;
use woven::yarn::profile::{Piece, Profile};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args_os().nth(1).map_or_else(
        || std::env::temp_dir().join("profile-masking.svg"),
        PathBuf::from,
    );
    let profile = Profile::new(0.9, 1.2)?;
    let psi: f64 = 1.15;
    let p = profile.period();
    let lit = profile.lit(psi);
    let (scale, margin) = (80.0, 30.0);
    let (u0, u1) = (-1.5 * p, 1.5 * p);
    let (w0, w1) = (-profile.depth() - 0.3, 1.6);
    let width = (u1 - u0) * scale + 2.0 * margin;
    let height = (w1 - w0) * scale + 2.0 * margin;
    let x = |u: f64| margin + (u - u0) * scale;
    let y = |w: f64| margin + (w1 - w) * scale;
    let mut svg = String::new();
    writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="13">"#
    )?;
    writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#)?;
    // A polyline of one piece over the parameter range (a, b), shifted by k periods.
    let path = |piece: Piece, a: f64, b: f64, k: f64| -> String {
        let n = if piece == Piece::Arc { 64 } else { 1 };
        (0..=n)
            .map(|i| {
                let t = a + (b - a) * i as f64 / n as f64;
                let (u, w) = profile.point(piece, t);
                format!("{:.2},{:.2}", x(u + k * p), y(w))
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    for k in [-1.0, 0.0, 1.0] {
        for piece in Piece::ALL {
            let (a, b) = profile.parameter_range(piece);
            writeln!(
                svg,
                r##"<polyline points="{}" fill="none" stroke="#888" stroke-width="2"/>"##,
                path(piece, a, b, k)
            )?;
            if let Some((lo, hi)) = lit.get(piece) {
                writeln!(
                    svg,
                    r##"<polyline points="{}" fill="none" stroke="#e67e00" stroke-width="5" stroke-linecap="round"/>"##,
                    path(piece, lo, hi, k)
                )?;
            }
        }
    }
    // Ray-casting verdict on period 0: dots 8 px outside the profile along the normal.
    for piece in Piece::ALL {
        let (a, b) = profile.parameter_range(piece);
        for i in 0..40 {
            let t = a + (b - a) * (i as f64 + 0.5) / 40.0;
            let (pt, n) = (profile.point(piece, t), profile.normal(piece, t));
            let on = woven::yarn::raycast::is_lit(&profile, pt, n, psi);
            let (cx, cy) = (x(pt.0) + 8.0 * n.0, y(pt.1) - 8.0 * n.1);
            let fill = if on { "#e67e00" } else { "white" };
            writeln!(
                svg,
                r##"<circle cx="{cx:.2}" cy="{cy:.2}" r="2.5" fill="{fill}" stroke="#e67e00"/>"##
            )?;
        }
    }
    // The silhouette point S of the right neighbour's arc and the shadow line through it.
    let s = (p - psi.cos(), psi.sin() - 1.0);
    let d = (psi.sin(), psi.cos());
    let (back, ahead) = (-2.4, 1.2);
    writeln!(
        svg,
        r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#333" stroke-dasharray="6 4"/>"##,
        x(s.0 + back * d.0),
        y(s.1 + back * d.1),
        x(s.0 + ahead * d.0),
        y(s.1 + ahead * d.1)
    )?;
    writeln!(
        svg,
        r##"<circle cx="{:.2}" cy="{:.2}" r="4" fill="#333"/><text x="{:.2}" y="{:.2}">S</text>"##,
        x(s.0),
        y(s.1),
        x(s.0) + 8.0,
        y(s.1) + 16.0
    )?;
    // Light arrows, toward the surface along −d, over the right-hand period.
    for k in 0..4 {
        let tip = (0.45 * p + 0.55 * k as f64, 0.55 - 0.1 * k as f64);
        let base = (tip.0 + 0.8 * d.0, tip.1 + 0.8 * d.1);
        writeln!(
            svg,
            r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#c9a000" stroke-width="1.5" marker-end="url(#a)"/>"##,
            x(base.0),
            y(base.1),
            x(tip.0),
            y(tip.1)
        )?;
    }
    svg.insert_str(
        svg.find("<rect").ok_or("no <rect> in the drawing")?,
        "<defs><marker id=\"a\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#c9a000\"/></marker></defs>\n",
    );
    writeln!(
        svg,
        r##"<text x="{:.2}" y="{:.2}">θa = 0.9, L = 1.2, ψ = 1.15 (onset π/2 − θa = 0.67): orange = Profile::lit; dots = ray casting (filled = lit); dashed = shadow line through S</text>"##,
        margin,
        height - 8.0
    )?;
    writeln!(svg, "</svg>")?;
    std::fs::write(&out, svg)?;
    println!("wrote {}", out.display());
    Ok(())
}
