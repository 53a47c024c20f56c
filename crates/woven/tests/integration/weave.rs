//! Weave patterns: named constructors, matrices, WIF files (paper Eq. (23); docs/spec.md §2.7).

use std::path::PathBuf;
use woven::weave::Pattern;
use woven::Error;

/// A WIF file of `tests/data/wif`.
fn wif_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/wif")
        .join(name)
}

/// Reads a WIF file of `tests/data/wif`, failing the test with the error.
fn wif(name: &str) -> Pattern {
    Pattern::from_wif_path(wif_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn named(name: &str) -> Pattern {
    Pattern::from_name(name).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// Whether `a` and `b` tile the plane identically after some cyclic shift of `a`, compared by
/// brute force over the common period (lcm of the sizes) with `is_weft`'s wrap-around; this is
/// independent of `Pattern::is_shift_of` and `minimal_repeat`, which it also checks.
fn same_up_to_shift(a: &Pattern, b: &Pattern) -> bool {
    let rows = a.rows() / gcd(a.rows(), b.rows()) * b.rows();
    let cols = a.cols() / gcd(a.cols(), b.cols()) * b.cols();
    let brute = (0..a.rows()).any(|dr| {
        (0..a.cols()).any(|dc| {
            (0..rows).all(|r| (0..cols).all(|c| a.is_weft(r + dr, c + dc) == b.is_weft(r, c)))
        })
    });
    assert_eq!(
        brute,
        a.is_shift_of(b),
        "Pattern::is_shift_of disagrees with brute force on\n{a}\nand\n{b}"
    );
    brute
}

/// The weft columns of row `r`.
fn weft_cols(p: &Pattern, r: usize) -> Vec<usize> {
    (0..p.cols()).filter(|&c| p.is_weft(r, c)).collect()
}

/// The weft rows of column `c`.
fn weft_rows(p: &Pattern, c: usize) -> Vec<usize> {
    (0..p.rows()).filter(|&r| p.is_weft(r, c)).collect()
}

#[track_caller]
fn assert_fraction(p: &Pattern, want: f64, what: &str) {
    let got = p.weft_fraction();
    assert!(
        (got - want).abs() < 1e-15,
        "{what}: weft fraction {got}, want {want}, tolerance 1e-15\n{p}"
    );
}

/// The message of a parse error, checking that it names `origin`.
#[track_caller]
fn parse_message(result: woven::Result<Pattern>, origin: &str) -> String {
    match result {
        Err(Error::Parse { path, message }) => {
            assert_eq!(path, origin);
            let shown = Error::Parse {
                path: path.clone(),
                message: message.clone(),
            }
            .to_string();
            assert!(shown.starts_with(origin), "{shown}");
            message
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// The `name` and `value` of an invalid-parameter error.
#[track_caller]
fn invalid(result: woven::Result<Pattern>) -> (String, String, String) {
    match result {
        Err(Error::InvalidParameter {
            name,
            value,
            expected,
        }) => (name, value, expected),
        other => panic!("expected an invalid-parameter error, got {other:?}"),
    }
}

// ---- named weaves -------------------------------------------------------------------------

#[test]
fn named_weft_fractions_match_model_md() {
    // docs/spec.md §2.7: plain 1/2, 2/1 twill 1/3 (its reverse 2/3), 5-harness satin 1/5 or 4/5.
    assert_fraction(&named("plain"), 0.5, "plain");
    assert_fraction(&named("twill-2/1"), 1.0 / 3.0, "twill-2/1");
    assert_fraction(&named("twill-1/2"), 2.0 / 3.0, "twill-1/2");
    assert_fraction(&named("twill-2/2"), 0.5, "twill-2/2");
    assert_fraction(&named("satin-5"), 0.2, "satin-5");
    assert_fraction(&named("sateen-5"), 0.8, "sateen-5");
    for (over, under) in [(1, 1), (3, 1), (1, 3), (3, 2), (4, 4), (7, 1)] {
        let t = Pattern::twill(over, under).unwrap();
        assert_eq!((t.rows(), t.cols()), (over + under, over + under));
        assert_fraction(
            &t,
            under as f64 / (over + under) as f64,
            &format!("twill {over}/{under}"),
        );
    }
}

#[test]
fn plain_is_a_checkerboard() {
    let p = Pattern::plain().unwrap();
    assert_eq!(p.to_matrix(), vec![vec![0, 1], vec![1, 0]]);
    assert_eq!(p, Pattern::twill(1, 1).unwrap());
    for r in 0..4 {
        for c in 0..4 {
            assert_eq!(p.is_weft(r, c), (r + c) % 2 == 1, "({r}, {c})");
        }
    }
}

#[test]
fn twill_is_diagonal() {
    for (over, under) in [(2, 1), (1, 2), (2, 2), (3, 1), (3, 2), (5, 3)] {
        let t = Pattern::twill(over, under).unwrap();
        let n = over + under;
        for r in 0..n {
            // Each pick is the previous one shifted by one end.
            for c in 0..n {
                assert_eq!(
                    t.is_weft(r + 1, c + 1),
                    t.is_weft(r, c),
                    "{over}/{under} ({r}, {c})"
                );
            }
            // Each pick: `under` weft cells, contiguous (cyclically), so `over` warp cells.
            assert_eq!(weft_cols(&t, r).len(), under, "{over}/{under} row {r}");
        }
        for c in 0..n {
            // Each warp end passes over `over` consecutive picks: exactly one warp→weft change.
            let warp_runs = (0..n)
                .filter(|&r| !t.is_weft(r, c) && t.is_weft(r + 1, c))
                .count();
            assert_eq!(warp_runs, 1, "{over}/{under} column {c}\n{t}");
            assert_eq!(
                n - weft_rows(&t, c).len(),
                over,
                "{over}/{under} column {c}"
            );
        }
    }
}

#[test]
fn satin_one_weft_cell_per_row_and_column_and_no_touching() {
    for n in [5, 7, 8, 9, 10, 11, 12] {
        let s = Pattern::satin(n).unwrap();
        assert_eq!((s.rows(), s.cols()), (n, n));
        assert_fraction(&s, 1.0 / n as f64, &format!("satin-{n}"));
        for i in 0..n {
            assert_eq!(weft_cols(&s, i).len(), 1, "satin-{n} row {i}\n{s}");
            assert_eq!(weft_rows(&s, i).len(), 1, "satin-{n} column {i}\n{s}");
        }
        // The weft floats of neighbouring picks never touch, not even across the wrap:
        // their columns differ by at least 2 cyclically.
        for r in 0..n {
            let a = weft_cols(&s, r)[0];
            let b = weft_cols(&s, r + 1)[0];
            let d = (b + n - a) % n;
            assert!(
                d >= 2 && d <= n - 2,
                "satin-{n} rows {r}, {}: {a} and {b}\n{s}",
                r + 1
            );
        }
        // Sateen is the complement.
        let t = Pattern::sateen(n).unwrap();
        assert_eq!(t, s.complement());
        assert_fraction(&t, (n - 1) as f64 / n as f64, &format!("sateen-{n}"));
    }
}

#[test]
fn satin_uses_the_smallest_coprime_step() {
    for (n, step) in [(5, 2), (7, 2), (8, 3), (10, 3), (12, 5)] {
        let s = Pattern::satin(n).unwrap();
        for r in 0..n {
            assert_eq!(weft_cols(&s, r), vec![step * r % n], "satin-{n} row {r}");
        }
    }
}

#[test]
fn satin_without_a_regular_step_is_an_error() {
    for n in [0, 1, 2, 3, 4, 6] {
        let (name, value, expected) = invalid(Pattern::satin(n));
        assert_eq!((name.as_str(), value), ("weave.satin.n", n.to_string()));
        assert!(
            expected.contains("n ≥ 5") && expected.contains("n ≠ 6"),
            "{expected}"
        );
        let (name, _, _) = invalid(Pattern::sateen(n));
        assert_eq!(name, "weave.sateen.n");
    }
    let shown = Pattern::satin(6).unwrap_err().to_string();
    assert!(
        shown.contains("weave.satin.n") && shown.contains("= 6"),
        "{shown}"
    );
    assert!(Pattern::satin(woven::weave::MAX_THREADS + 1).is_err());
}

#[test]
fn twill_errors_name_the_parameter() {
    assert_eq!(invalid(Pattern::twill(0, 1)).0, "weave.twill.over");
    assert_eq!(invalid(Pattern::twill(1, 0)).0, "weave.twill.under");
    assert_eq!(invalid(Pattern::twill(4000, 200)).0, "weave.twill");
}

// ---- names ----------------------------------------------------------------------------------

#[test]
fn from_name_round_trips() {
    for name in [
        "plain",
        "twill-2/1",
        "twill-1/2",
        "twill-2/2",
        "twill-3/1",
        "twill-1/3",
        "twill-5/3",
        "satin-5",
        "satin-7",
        "satin-8",
        "satin-12",
        "sateen-5",
        "sateen-8",
        "sateen-11",
    ] {
        let p = named(name);
        assert_eq!(p.name().as_deref(), Some(name), "{name}\n{p}");
        assert_eq!(name.parse::<Pattern>().unwrap(), p, "{name} via FromStr");
    }
    // Case and surrounding space are ignored; twill-1/1 is the plain weave.
    assert_eq!(named("  Satin-5 "), named("satin-5"));
    assert_eq!(named("TWILL-1/1").name().as_deref(), Some("plain"));
}

#[test]
fn name_finds_named_weaves_up_to_shift_only() {
    // A shifted, twice-drafted satin is still satin-5.
    let satin = named("satin-5");
    let shifted: Vec<Vec<u8>> = (0..10)
        .map(|r| {
            (0..10)
                .map(|c| u8::from(satin.is_weft(r + 3, c + 1)))
                .collect()
        })
        .collect();
    let shifted = Pattern::from_matrix(shifted).unwrap();
    assert_eq!(shifted.name().as_deref(), Some("satin-5"));
    // A mirrored twill, a basket weave and a satin with step 3 are not named weaves.
    let mirrored = Pattern::from_matrix(vec![vec![1, 0, 0], vec![0, 0, 1], vec![0, 1, 0]]).unwrap();
    assert!(!mirrored.is_shift_of(&named("twill-2/1")));
    assert_eq!(mirrored.name(), None);
    let basket = Pattern::from_matrix(vec![
        vec![0, 0, 1, 1],
        vec![0, 0, 1, 1],
        vec![1, 1, 0, 0],
        vec![1, 1, 0, 0],
    ])
    .unwrap();
    assert_eq!(basket.name(), None);
    let step3: Vec<Vec<u8>> = (0..5)
        .map(|r| (0..5).map(|c| u8::from(c == 3 * r % 5)).collect())
        .collect();
    assert_eq!(Pattern::from_matrix(step3).unwrap().name(), None);
}

#[test]
fn from_name_errors_list_the_valid_forms() {
    for bad in [
        "",
        "satin",
        "satin5",
        "satin-",
        "satin-x",
        "satin-+5",
        "twill-2",
        "twill-2/",
        "twill/2/1",
        "serge",
        "plain-2",
    ] {
        let (name, value, expected) = invalid(Pattern::from_name(bad));
        assert_eq!(name, "weave.pattern", "{bad:?}");
        assert_eq!(value, format!("{bad:?}"));
        for form in ["plain", "twill-N/M", "satin-N", "sateen-N"] {
            assert!(expected.contains(form), "{bad:?}: {expected}");
        }
    }
    // Well-formed names with numbers out of range report the constructor's parameter.
    assert_eq!(invalid(Pattern::from_name("satin-6")).0, "weave.satin.n");
    assert_eq!(invalid(Pattern::from_name("sateen-4")).0, "weave.sateen.n");
    assert_eq!(
        invalid(Pattern::from_name("twill-0/3")).0,
        "weave.twill.over"
    );
}

// ---- matrices -------------------------------------------------------------------------------

#[test]
fn from_matrix_round_trips_and_displays() {
    let m = vec![vec![0, 1, 1], vec![1, 0, 0]];
    let p = Pattern::from_matrix(m.clone()).unwrap();
    assert_eq!((p.rows(), p.cols()), (2, 3));
    assert_eq!(p.to_matrix(), m);
    assert_eq!(p.to_string(), ".##\n#..");
    assert_fraction(&p, 0.5, "2 × 3");
    assert_eq!(
        named("satin-5").to_string(),
        "#....\n..#..\n....#\n.#...\n...#."
    );
}

#[test]
fn from_matrix_errors_name_the_offence() {
    let (name, value, _) = invalid(Pattern::from_matrix(vec![]));
    assert_eq!(name, "weave.pattern");
    assert!(value.contains("0 × 0"), "{value}");
    assert_eq!(
        invalid(Pattern::from_matrix(vec![vec![]])).0,
        "weave.pattern"
    );

    let (name, value, expected) = invalid(Pattern::from_matrix(vec![
        vec![0, 1],
        vec![1, 0],
        vec![1, 0, 1],
    ]));
    assert_eq!(name, "weave.pattern");
    assert!(
        value.contains("row 2") && value.contains("3 columns"),
        "{value}"
    );
    assert!(expected.contains("rectangular"), "{expected}");

    let (name, value, expected) = invalid(Pattern::from_matrix(vec![vec![0, 1], vec![2, 0]]));
    assert_eq!(name, "weave.pattern");
    assert_eq!(value, "2 at row 1, column 0");
    assert!(
        expected.contains("0") && expected.contains("1"),
        "{expected}"
    );
}

#[test]
fn is_weft_and_uv_wrap_around() {
    let p = named("twill-2/1");
    let (rows, cols) = (p.rows(), p.cols());
    for r in 0..rows {
        for c in 0..cols {
            let want = p.to_matrix()[r][c] == 1;
            assert_eq!(p.is_weft(r + 7 * rows, c + 5 * cols), want);
            // The centre and the corners of the cell, in this and other repeats.
            for (du, dv) in [(0.5, 0.5), (0.001, 0.001), (0.999, 0.999)] {
                let u = (c as f64 + du) / cols as f64;
                let v = (r as f64 + dv) / rows as f64;
                for (ku, kv) in [
                    (0.0, 0.0),
                    (1.0, 0.0),
                    (0.0, -1.0),
                    (-3.0, 12.0),
                    (1e6, -1e6),
                ] {
                    assert_eq!(
                        p.weft_at_uv(u + ku, v + kv),
                        want,
                        "u = {}, v = {}, cell ({r}, {c})",
                        u + ku,
                        v + kv
                    );
                }
            }
        }
    }
    // u runs along the columns (weft, x) and v along the rows (warp, y).
    let stripe = Pattern::from_matrix(vec![vec![1, 0]]).unwrap();
    assert!(stripe.weft_at_uv(0.25, 0.9) && !stripe.weft_at_uv(0.75, 0.1));
    assert!(stripe.weft_at_uv(-0.75, 0.0) && !stripe.weft_at_uv(-0.25, 0.0));
}

#[test]
fn minimal_repeat_finds_the_smallest_tile() {
    // Tiled repeats reduce to the named tile exactly (the tile is the top-left corner).
    for name in ["plain", "twill-2/1", "twill-3/2", "satin-8", "sateen-5"] {
        let tile = named(name);
        for (kr, kc) in [(1, 1), (2, 3), (4, 1)] {
            let big: Vec<Vec<u8>> = (0..kr * tile.rows())
                .map(|r| {
                    (0..kc * tile.cols())
                        .map(|c| u8::from(tile.is_weft(r, c)))
                        .collect()
                })
                .collect();
            let big = Pattern::from_matrix(big).unwrap();
            assert_eq!(big.minimal_repeat(), tile, "{name} × ({kr}, {kc})");
        }
    }
    // Rectangular tiles: stripes and a 2 × 3 block.
    let stripes = Pattern::from_matrix(vec![vec![1, 0, 0, 1, 0, 0]; 4]).unwrap();
    assert_eq!(stripes.minimal_repeat().to_matrix(), vec![vec![1, 0, 0]]);
    let block = vec![vec![1, 1, 0], vec![0, 0, 0]];
    let tiled: Vec<Vec<u8>> = (0..6).map(|r| block[r % 2].repeat(2)).collect();
    assert_eq!(
        Pattern::from_matrix(tiled)
            .unwrap()
            .minimal_repeat()
            .to_matrix(),
        block
    );
    // A pattern without a smaller repeat is its own, and uniform patterns reduce to 1 × 1.
    let odd = Pattern::from_matrix(vec![vec![1, 0, 0, 0], vec![0, 0, 1, 1]]).unwrap();
    assert_eq!(odd.minimal_repeat(), odd);
    let blank = Pattern::from_matrix(vec![vec![0; 6]; 4]).unwrap();
    assert_eq!(blank.minimal_repeat().to_matrix(), vec![vec![0]]);
}

#[test]
fn shift_comparison_agrees_with_brute_force() {
    let twill = named("twill-2/1");
    let shifted = Pattern::from_matrix(
        (0..3)
            .map(|r| {
                (0..3)
                    .map(|c| u8::from(twill.is_weft(r + 1, c + 2)))
                    .collect()
            })
            .collect(),
    )
    .unwrap();
    assert_ne!(shifted, twill);
    assert!(same_up_to_shift(&shifted, &twill));
    assert!(!same_up_to_shift(&twill, &named("twill-1/2")));
    assert!(!same_up_to_shift(&twill, &named("plain")));
    assert!(!same_up_to_shift(&named("satin-5"), &named("twill-4/1")));
    assert!(same_up_to_shift(&named("plain"), &named("twill-1/1")));
}

// ---- WIF files ------------------------------------------------------------------------------

#[test]
fn wif_plain() {
    let p = wif("plain.wif");
    assert_eq!(
        p.to_matrix(),
        vec![
            vec![0, 1, 0, 1],
            vec![1, 0, 1, 0],
            vec![0, 1, 0, 1],
            vec![1, 0, 1, 0]
        ]
    );
    assert_fraction(&p, 0.5, "plain.wif");
    assert!(same_up_to_shift(&p, &named("plain")));
    assert_eq!(p.minimal_repeat(), named("plain"));
    assert_eq!(p.name().as_deref(), Some("plain"));
}

#[test]
fn wif_twill_2_1() {
    let p = wif("twill-2-1.wif");
    assert_eq!((p.rows(), p.cols()), (6, 6));
    assert_eq!(
        p.to_string(),
        "..#..#\n#..#..\n.#..#.\n..#..#\n#..#..\n.#..#."
    );
    assert_fraction(&p, 1.0 / 3.0, "twill-2-1.wif");
    assert!(same_up_to_shift(&p, &named("twill-2/1")));
    assert!(!same_up_to_shift(&p, &named("twill-1/2")));
    assert_eq!(p.name().as_deref(), Some("twill-2/1"));
}

#[test]
fn wif_twill_2_2_sizes_from_largest_index() {
    let p = wif("twill-2-2.wif");
    assert_eq!((p.rows(), p.cols()), (8, 8));
    assert_fraction(&p, 0.5, "twill-2-2.wif");
    assert!(same_up_to_shift(&p, &named("twill-2/2")));
    assert!(!same_up_to_shift(&p, &named("plain")));
    assert_eq!(p.minimal_repeat().rows(), 4);
}

#[test]
fn wif_satin_5() {
    let p = wif("satin-5.wif");
    assert_eq!((p.rows(), p.cols()), (5, 10));
    assert_eq!(
        p.to_string(),
        "#....#....\n..#....#..\n....#....#\n.#....#...\n...#....#."
    );
    assert_fraction(&p, 0.2, "satin-5.wif");
    assert!(same_up_to_shift(&p, &named("satin-5")));
    assert_eq!(p.minimal_repeat(), named("satin-5"));
    for r in 0..p.rows() {
        assert_eq!(weft_cols(&p, r).len(), 2, "two repeats across, row {r}");
    }
    for c in 0..p.cols() {
        assert_eq!(weft_rows(&p, c).len(), 1, "column {c}");
    }
}

#[test]
fn wif_sinking_shed_inverts() {
    let p = wif("sateen-5-sinking.wif");
    assert_fraction(&p, 0.8, "sateen-5-sinking.wif");
    assert!(same_up_to_shift(&p, &named("sateen-5")));
    assert_eq!(p, wif("satin-5.wif").minimal_repeat().complement());
    assert_eq!(p.name().as_deref(), Some("sateen-5"));
}

#[test]
fn wif_liftplan() {
    let p = wif("liftplan-twill-3-1.wif");
    assert_eq!((p.rows(), p.cols()), (8, 8));
    assert_fraction(&p, 0.25, "liftplan-twill-3-1.wif");
    assert!(same_up_to_shift(&p, &named("twill-3/1")));
    assert_eq!(p.name().as_deref(), Some("twill-3/1"));
}

#[test]
fn wif_string_rules() {
    let base = "[WIF]\n[WEAVING]\nShafts=2\n[THREADING]\n1=1\n2=2\n4=1\n";
    // End 3 has no threading: never lifted, so weft on top along the whole column.
    let p = Pattern::from_wif_str(&format!("{base}[LIFTPLAN]\n1=1\n2=2\n"), "<s>").unwrap();
    assert_eq!(p.to_string(), ".##.\n#.##");
    // Declared thread counts add unthreaded ends and empty picks (weft on top).
    let p = Pattern::from_wif_str(
        &format!("{base}[WARP]\nThreads=5\n[WEFT]\nThreads=3\n[LIFTPLAN]\n1=1\n2=2\n"),
        "<s>",
    )
    .unwrap();
    assert_eq!(p.to_string(), ".##.#\n#.###\n#####");
    // TREADLING with several treadles per pick lifts the union of their shafts; a treadle
    // with no tie-up entry lifts nothing; a LIFTPLAN beside them is an error (one would be
    // ignored).
    let tieup = format!("{base}[TIEUP]\n1=1\n2=\n[TREADLING]\n1=1,2\n2=2\n3=1\n");
    let p = Pattern::from_wif_str(&tieup, "<s>").unwrap();
    assert_eq!(p.to_string(), ".##.\n####\n.##.");
    assert!(Pattern::from_wif_str(&format!("{tieup}[LIFTPLAN]\n1=2\n"), "<s>").is_err());
    // Sinking shed: the marked shafts go down, the unthreaded end stays up (warp on top).
    let p = Pattern::from_wif_str(
        &format!("{base}[LIFTPLAN]\n1=1\n2=2\n").replace("Shafts=2", "Shafts=2\nRising Shed=False"),
        "<s>",
    )
    .unwrap();
    assert_eq!(p.to_string(), "#..#\n.#..");
}

#[test]
fn wif_errors_name_origin_section_and_line() {
    let cases = [
        ("bad-line.wif", "line 11", "[THREADING]", "malformed line"),
        (
            "bad-number.wif",
            "line 17",
            "[TREADLING]",
            "`two` is not a whole number",
        ),
        (
            "shaft-out-of-range.wif",
            "line 14",
            "[TIEUP]",
            "shaft 3 out of range",
        ),
        (
            "treadle-out-of-range.wif",
            "line 20",
            "[TREADLING]",
            "treadle 4 out of range",
        ),
    ];
    for (file, line, section, what) in cases {
        let path = wif_path(file);
        let message = parse_message(Pattern::from_wif_path(&path), &path.display().to_string());
        for part in [line, section, what] {
            assert!(
                message.contains(part),
                "{file}: `{part}` not in `{message}`"
            );
        }
    }
    let path = wif_path("missing-threading.wif");
    let message = parse_message(Pattern::from_wif_path(&path), &path.display().to_string());
    assert!(message.contains("missing section [THREADING]"), "{message}");
}

#[test]
fn wif_missing_file_is_an_io_error() {
    match Pattern::from_wif_path(wif_path("no-such-file.wif")) {
        Err(Error::Io { path, .. }) => assert!(path.ends_with("no-such-file.wif")),
        other => panic!("expected an I/O error, got {other:?}"),
    }
}
