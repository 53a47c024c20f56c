//! Bad input never panics, never fills memory, never loads silently: every parser of the library
//! (material TOML, WIF, the direction CSV, `.wtab` tables, MERL files) against hostile input.
//! The coverage-guided fuzz targets in `fuzz/` go further; the properties here run in every
//! `cargo test`.

use proptest::prelude::*;
use std::io::Read;
use woven::bsdf::{Bsdf, Transport};
use woven::directions::{DirectionReader, DirectionRecord};
use woven::export::MerlBrdf;
use woven::material::Material;
use woven::table::{Table, TableOptions};
use woven::weave::Pattern;
use woven::{Error, Vec3};

/// A tiny, fast table of a flat fiber surface (isotropic) or of the belt cloth (mirror).
fn tiny_table(material: &str) -> Table {
    let m = Material::from_preset_or_path(material).unwrap();
    let options = TableOptions {
        n_theta: 3,
        n_phi: 2,
        n_h: 5,
        n_h_isotropic: 5,
        azimuth_nodes: 8,
        threads: 1,
        ..TableOptions::default()
    };
    let model = m.build(550.0).unwrap();
    Table::build(&model, &m, &options, &|_, _| {}).unwrap()
}

const FLAT: &str = "[fiber]\neta = 1.5\nroughness = 0.2\ndiffuse = 0.1\nnormalization = \"none\"\n";

fn flat_table() -> Table {
    let dir = std::env::temp_dir().join(format!("woven-robust-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("flat.toml");
    std::fs::write(&path, FLAT).unwrap();
    let t = tiny_table(path.to_str().unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
    t
}

/// A table file's bytes with its header text replaced by `edit(header)` and the payload by
/// `edit_payload`, header length and CRC made right again.
fn rewrite(
    bytes: &[u8],
    edit: impl Fn(&str) -> String,
    edit_payload: impl Fn(&mut [u8]),
) -> Vec<u8> {
    let hlen = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let header = std::str::from_utf8(&bytes[16..16 + hlen]).unwrap();
    let new_header = edit(header);
    let mut payload = bytes[16 + hlen..bytes.len() - 4].to_vec();
    edit_payload(&mut payload);
    let mut out = bytes[..12].to_vec();
    out.extend_from_slice(&(new_header.len() as u32).to_le_bytes());
    out.extend_from_slice(new_header.as_bytes());
    out.extend_from_slice(&payload);
    let crc = crc32(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// CRC-32 (IEEE), bit by bit: the tests do not need the library's dependency.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

fn replace_line(header: &str, key: &str, line: Option<&str>) -> String {
    let mut out = String::new();
    let mut in_material = false;
    for l in header.lines() {
        if l.starts_with("material = ") {
            in_material = true;
        }
        if !in_material && l.starts_with(&format!("{key} = ")) {
            if let Some(line) = line {
                out.push_str(line);
                out.push('\n');
            }
            continue;
        }
        out.push_str(l);
        out.push('\n');
    }
    out
}

fn table_error(bytes: &[u8]) -> String {
    match Table::from_bytes(bytes, "bad.wtab") {
        Ok(_) => panic!("a nonsense table loaded"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn table_headers_with_a_right_crc_but_nonsense_are_refused() {
    let bytes = flat_table().to_bytes();
    assert!(Table::from_bytes(&rewrite(&bytes, str::to_string, |_| {}), "ok.wtab").is_ok());
    let cases: &[(&str, Option<&str>, &str)] = &[
        (
            "wavelength_nm",
            Some("wavelength_nm = -550.0"),
            "`wavelength_nm` = -550.0",
        ),
        (
            "wavelength_nm",
            Some("wavelength_nm = nan"),
            "`wavelength_nm` = nan",
        ),
        ("wavelength_nm", Some("wavelength_nm = 0.0"), "[200, 2500]"),
        ("wavelength_nm", None, "`wavelength_nm` is missing"),
        ("theta_max", Some("theta_max = 0.0"), "`theta_max` = 0.0"),
        ("theta_max", Some("theta_max = -1.0"), "`theta_max` = -1.0"),
        (
            "theta_max",
            Some("theta_max = 1.5707963267948966"),
            "less than π/2",
        ),
        ("theta_max", Some("theta_max = inf"), "`theta_max` = inf"),
        ("n_theta", Some("n_theta = 1"), "`n_theta` = 1"),
        ("n_theta", Some("n_theta = 4"), "values, but the grid needs"),
        (
            "n_h",
            Some("n_h = 9223372036854775807"),
            "`n_h` = 9223372036854775807",
        ),
        ("n_phi", Some("n_phi = 2"), "`n_phi` = 2"),
        ("symmetry", Some("symmetry = \"mirror\""), "`n_phi` = 1"),
        ("symmetry", Some("symmetry = 3"), "`symmetry`"),
    ];
    for &(key, line, want) in cases {
        let bad = rewrite(&bytes, |h| replace_line(h, key, line), |_| {});
        let m = table_error(&bad);
        assert!(
            m.starts_with("bad.wtab: not a valid woven table") && m.contains(want),
            "{key} → {line:?}: `{m}` lacks `{want}`"
        );
    }
    // No material, or an empty one.
    let cut = |h: &str| h[..h.find("material = ").unwrap()].to_string();
    let m = table_error(&rewrite(&bytes, cut, |_| {}));
    assert!(m.contains("`material` is missing"), "{m}");
    let empty = |h: &str| format!("{}material = \"  \"\n", cut(h));
    let m = table_error(&rewrite(&bytes, empty, |_| {}));
    assert!(m.contains("`material` is empty"), "{m}");
    // All-zero sampling densities: the cells are the payload after the values.
    let zero_cells = |p: &mut [u8]| {
        let n = u64::from_le_bytes(p[..8].try_into().unwrap()) as usize;
        for b in &mut p[8 + 4 * n + 8..] {
            *b = 0;
        }
    };
    let m = table_error(&rewrite(&bytes, str::to_string, zero_cells));
    assert!(m.contains("every sampling density is zero"), "{m}");
}

#[cfg(unix)]
#[test]
fn endless_streams_are_refused_without_filling_memory() {
    let zero = std::path::Path::new("/dev/zero");
    // Material, WIF (also behind a material's `{ wif = … }`), table, MERL: a device is not a
    // regular file, refused before it is opened or read.
    let device = |m: String, what: &str| {
        assert!(
            m.contains(&format!(
                "/dev/zero: a character device, not a regular file: {what} is read only from \
                 a regular file"
            )),
            "{m}"
        )
    };
    device(
        Material::from_path(zero).unwrap_err().to_string(),
        "a material file",
    );
    device(
        Pattern::from_wif_path(zero).unwrap_err().to_string(),
        "a WIF file",
    );
    let toml = format!("{FLAT}[yarn]\nlateral_length = 1.0\nslope_mean = 0.5\n[weave]\npattern = {{ wif = \"/dev/zero\" }}\n");
    let m = Material::from_toml_str(&toml, "<test>")
        .unwrap_err()
        .to_string();
    device(m, "a WIF file");
    device(Table::load(zero).unwrap_err().to_string(), "a table");
    device(
        MerlBrdf::load(zero).unwrap_err().to_string(),
        "a MERL BRDF file",
    );
    // Directions: an endless line.
    let m = DirectionReader::new(std::fs::File::open(zero).unwrap(), "/dev/zero")
        .unwrap_err()
        .to_string();
    assert!(m.contains("/dev/zero") && m.contains("longer than"), "{m}");
}

#[test]
fn a_table_stream_is_read_no_further_than_its_counts() {
    let dir = std::env::temp_dir().join(format!("woven-robust-t-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge-header.wtab");
    // The magic, the version, and a header length of 4 GiB: refused before reading on.
    let mut bytes = b"WOVENTAB".to_vec();
    bytes.extend_from_slice(&1u32.to_le_bytes());
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    std::fs::write(&path, &bytes).unwrap();
    let m = Table::load(&path).unwrap_err().to_string();
    assert!(m.contains("header of 4294967295 bytes"), "{m}");
    // A complete table followed by more bytes: trailing bytes, not read to their end.
    let mut bytes = flat_table().to_bytes();
    std::fs::write(&path, &bytes).unwrap();
    assert!(Table::load(&path).is_ok());
    bytes.extend_from_slice(&[0; 100]);
    std::fs::write(&path, &bytes).unwrap();
    let m = Table::load(&path).unwrap_err().to_string();
    assert!(m.contains("trailing"), "{m}");
    // Truncated anywhere: an error, never a panic.
    let good = flat_table().to_bytes();
    for cut in [
        0,
        7,
        15,
        16,
        40,
        good.len() / 2,
        good.len() - 5,
        good.len() - 1,
    ] {
        std::fs::write(&path, &good[..cut]).unwrap();
        assert!(Table::load(&path).is_err(), "cut at {cut}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_cauchy_index_is_checked_at_the_wavelength_used() {
    // η(380 nm) = 3.77 is fine; η(200 nm) = 11 is not.
    let toml = "[fiber]\neta = { cauchy_a = 1.0, cauchy_b_nm2 = 400000.0 }\nroughness = 0.2\nnormalization = \"none\"\n";
    let m = Material::from_toml_str(toml, "<test>").unwrap();
    assert!(m.build(550.0).is_ok());
    assert!(m.build(380.0).is_ok());
    match m.build(200.0) {
        Err(Error::InvalidParameter { name, value, .. }) => {
            assert_eq!(name, "fiber.eta");
            assert!(value.contains("at 200 nm"), "{value}");
        }
        other => panic!("expected an invalid fiber.eta, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn nan_and_infinity_anywhere_in_a_material_name_the_key() {
    let base = "[fiber]\nmodel = \"rough\"\neta = 1.5\nroughness = 0.2\ndiffuse = 0.1\n\
                [yarn]\nlateral_length = 2.0\nslope_mean = 0.5\nslope_std = 0.3\n\
                interreflection = 0.2\ninterreflection_albedo = 0.5\ntwist_std = 0.1\n\
                [weave]\nweft_fraction = 0.5\n";
    Material::from_toml_str(base, "<test>").unwrap();
    let keys = [
        ("eta = 1.5", "fiber.eta"),
        ("roughness = 0.2", "fiber.roughness"),
        ("diffuse = 0.1", "fiber.diffuse"),
        ("lateral_length = 2.0", "yarn.lateral_length"),
        ("slope_mean = 0.5", "yarn.slope_mean"),
        ("slope_std = 0.3", "yarn.slope_std"),
        ("interreflection = 0.2", "yarn.interreflection"),
        (
            "interreflection_albedo = 0.5",
            "yarn.interreflection_albedo",
        ),
        ("twist_std = 0.1", "yarn.twist_std"),
        ("weft_fraction = 0.5", "weave.weft_fraction"),
    ];
    for (line, key) in keys {
        for bad in ["nan", "inf", "-inf", "+nan"] {
            let (k, _) = line.split_once(" = ").unwrap();
            let text = base.replacen(line, &format!("{k} = {bad}"), 1);
            let e = Material::from_toml_str(&text, "<test>")
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{key} = {bad}: {e}");
        }
    }
    let cauchy = base.replace("eta = 1.5", "eta = { cauchy_a = 1.5, cauchy_b_nm2 = nan }");
    let e = Material::from_toml_str(&cauchy, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("fiber.eta.cauchy_b_nm2"), "{e}");
    let htsg = "[fiber]\nmodel = \"htsg\"\neta = 1.5\nsigma_h_um = inf\ntau_um = 2.0\n";
    let e = Material::from_toml_str(htsg, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("sigma_h_um"), "{e}");
    let htsg = "[fiber]\nmodel = \"htsg\"\neta = 1.5\nsigma_h_um = 0.2\ntau_um = nan\n";
    let e = Material::from_toml_str(htsg, "<test>")
        .unwrap_err()
        .to_string();
    assert!(e.contains("tau_um"), "{e}");
}

#[test]
fn a_huge_inline_matrix_is_refused_before_it_is_built() {
    let row = format!("[{}]", vec!["0"; 5000].join(","));
    let toml = format!(
        "{FLAT}[yarn]\nlateral_length = 1.0\nslope_mean = 0.5\n[weave]\npattern = [{row}]\n"
    );
    match Material::from_toml_str(&toml, "<test>") {
        Err(Error::InvalidParameter {
            name,
            value,
            expected,
        }) => {
            assert_eq!(name, "weave.pattern");
            assert!(value.contains("5000 columns"), "{value}");
            assert!(expected.contains("4096"), "{expected}");
        }
        other => panic!("expected an invalid pattern, got {:?}", other.map(|_| ())),
    }
}

/// A WIF text with sections `body` after `[WIF]`.
fn wif(body: &str) -> String {
    format!("[WIF]\nVersion=1.1\n{body}")
}

fn wif_error(text: &str) -> String {
    match Pattern::from_wif_str(text, "draft.wif") {
        Err(Error::Parse { path, message }) => {
            assert_eq!(path, "draft.wif");
            message
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn wif_the_same_end_twice_under_two_spellings_is_an_error() {
    let m = wif_error(&wif(
        "[THREADING]\n1=1\n01=2\n[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n",
    ));
    assert!(
        m.contains("line 5, section [THREADING]") && m.contains("key `01` is end 1 again"),
        "{m}"
    );
    assert!(m.contains("first at line 4 as `1`"), "{m}");
    let m = wif_error(&wif("[THREADING]\n1=1\n2=2\n[LIFTPLAN]\n1=1\n2=2\n002=1\n"));
    assert!(
        m.contains("section [LIFTPLAN]") && m.contains("`002` is pick 2 again"),
        "{m}"
    );
    let m = wif_error(&wif(
        "[THREADING]\n1=1\n2=2\n[TIEUP]\n1=1\n+1=2\n[TREADLING]\n1=1\n2=2\n",
    ));
    assert!(m.contains("[TIEUP]"), "{m}");
}

#[test]
fn wif_a_lift_plan_beside_tieup_and_treadling_is_an_error() {
    let m = wif_error(&wif(
        "[THREADING]\n1=1\n2=2\n[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n[LIFTPLAN]\n1=2\n2=1\n",
    ));
    assert!(
        m.contains("line 12, section [LIFTPLAN]") && m.contains("keep one of them"),
        "{m}"
    );
}

#[test]
fn wif_a_treadling_that_repeats_one_treadle_stays_small() {
    // 4096 ends on 4096 shafts, one treadle tied to every shaft, and every pick pressing it 64
    // times: once billions of list entries, now bit sets.
    let n = woven::weave::MAX_THREADS;
    let mut text = wif("[THREADING]\n");
    for e in 1..=n {
        text.push_str(&format!("{e}={e}\n"));
    }
    let all: Vec<String> = (1..=n).map(|s| s.to_string()).collect();
    text.push_str(&format!("[TIEUP]\n1={}\n[TREADLING]\n", all.join(",")));
    let ones = vec!["1"; 64].join(",");
    for p in 1..=n {
        text.push_str(&format!("{p}={ones}\n"));
    }
    let pattern = Pattern::from_wif_str(&text, "<test>").unwrap();
    assert_eq!((pattern.rows(), pattern.cols()), (n, n));
    // Every shaft rises on every pick: warp everywhere.
    assert_eq!(pattern.weft_fraction(), 0.0);
}

#[test]
fn refusing_a_file_that_is_not_a_wif_does_not_print_it() {
    for text in [
        "password=hunter2\n",
        "[hunter2\n",
        "hunter2\n[WIF]\n",
        "#!/bin/sh\necho hunter2\n",
    ] {
        let m = wif_error(text);
        assert!(!m.contains("hunter2"), "{m}");
        assert!(m.contains("line 1"), "{m}");
    }
    let m = wif_error("password=hunter2\n");
    assert!(m.contains("weaving information file"), "{m}");
}

/// A data row with `text` in place of one field, through the direction reader.
fn direction_row(text: &str) -> Result<[f64; 4], String> {
    let input = format!("theta_i,phi_i,theta_r,phi_r\n{text}\n");
    let mut reader = DirectionReader::new(input.as_bytes(), "dirs.csv").unwrap();
    let mut record = DirectionRecord::new();
    assert!(reader.read_record(&mut record).unwrap());
    record.angles().map_err(|e| e.to_string())
}

#[test]
fn nan_and_infinity_in_the_direction_csv_name_line_and_column() {
    assert!(direction_row("0.1,0.2,0.3,0.4").is_ok());
    for (row, column) in [
        ("NaN,0,0,0", "column 1 `theta_i`"),
        ("0,inf,0,0", "column 2 `phi_i`"),
        ("0,0,-inf,0", "column 3 `theta_r`"),
        ("0,0,0,infinity", "column 4 `phi_r`"),
        ("0,0,0,1e999", "column 4 `phi_r`"),
    ] {
        let m = direction_row(row).unwrap_err();
        assert!(m.starts_with(&format!("line 2, {column}")), "{row}: {m}");
        assert!(m.contains("not a finite number"), "{row}: {m}");
    }
}

/// Random edits of `seed`: each `(position, byte)` overwrites or, with the top bit, inserts.
fn mutate(seed: &[u8], edits: &[(usize, u8, bool)]) -> Vec<u8> {
    let mut out = seed.to_vec();
    for &(at, byte, insert) in edits {
        let at = at % (out.len() + 1);
        if insert || at == out.len() {
            out.insert(at, byte);
        } else {
            out[at] = byte;
        }
    }
    out
}

fn edits() -> impl Strategy<Value = Vec<(usize, u8, bool)>> {
    proptest::collection::vec((any::<usize>(), any::<u8>(), any::<bool>()), 1..8)
}

fn check_table_bytes(bytes: &[u8]) {
    if let Ok(t) = Table::from_bytes(bytes, "<prop>") {
        let (a, b) = (
            Vec3::from_spherical(0.4, 0.2),
            Vec3::from_spherical(1.2, 3.0),
        );
        let f = t.eval(a, b);
        assert!(f.is_finite() && f >= 0.0, "{f}");
        assert!(t.pdf_direction(a, b).is_finite());
        let _ = t.sample(a, 0.5, [0.3, 0.7], Transport::Radiance);
        let _ = t.sample(a, 0.5, [0.3, 0.7], Transport::Importance);
    }
}

fn check_material_text(text: &str) {
    if let Ok(m) = Material::from_toml_str(text, "<prop>") {
        let again = Material::from_toml_str(&m.to_self_contained_toml_string(), "<again>")
            .expect("a material's own TOML reads back");
        assert_eq!(again.fiber, m.fiber);
        assert_eq!(again.yarn, m.yarn);
    }
}

fn check_directions(bytes: &[u8]) {
    if let Ok(mut reader) = DirectionReader::new(bytes, "<prop>") {
        let mut record = DirectionRecord::new();
        while let Ok(true) = reader.read_record(&mut record) {
            if let Ok(angles) = record.angles() {
                assert!(angles.iter().all(|x| x.is_finite()));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn any_bytes_never_panic_any_parser(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        let text = String::from_utf8_lossy(&bytes);
        check_material_text(&text);
        let _ = Pattern::from_wif_str(&text, "<prop>");
        check_directions(&bytes);
        check_table_bytes(&bytes);
        let _ = MerlBrdf::read(&bytes[..]);
    }

    #[test]
    fn mutated_presets_never_panic(preset in 0usize..Material::preset_names().len(), edits in edits()) {
        let name = Material::preset_names()[preset];
        let seed = Material::preset_toml(name).unwrap().as_bytes();
        check_material_text(&String::from_utf8_lossy(&mutate(seed, &edits)));
    }

    #[test]
    fn mutated_wifs_never_panic(file in 0usize..4, edits in edits()) {
        let name = ["plain", "twill-2-1", "satin-5", "liftplan-twill-3-1"][file];
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("tests/data/wif/{name}.wif"));
        let seed = std::fs::read(path).unwrap();
        let text = String::from_utf8_lossy(&mutate(&seed, &edits)).into_owned();
        if let Ok(p) = Pattern::from_wif_str(&text, "<prop>") {
            prop_assert!((0.0..=1.0).contains(&p.weft_fraction()));
        }
    }

    #[test]
    fn mutated_direction_csv_never_panics(edits in edits()) {
        let seed = b"theta_i,phi_i,theta_r,phi_r\n0.5,0,0.5,2.5\n0.1,1e-3,1.5707963267948966,-7\n";
        check_directions(&mutate(seed, &edits));
    }

    #[test]
    fn mutated_tables_with_a_right_crc_never_panic(edits in edits()) {
        let good = tiny_flat_bytes();
        let mut bytes = mutate(&good[..good.len() - 4], &edits);
        let crc = crc32(&bytes);
        bytes.extend_from_slice(&crc.to_le_bytes());
        check_table_bytes(&bytes);
    }
}

/// The bytes of the tiny flat table, built once.
fn tiny_flat_bytes() -> &'static [u8] {
    static BYTES: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    BYTES.get_or_init(|| flat_table().to_bytes())
}

#[test]
fn merl_reader_reads_at_most_one_byte_past_a_file() {
    // A stream of a valid header then endless zeros: the reader stops after the blocks and one
    // more byte.
    let mut header = Vec::new();
    for d in [90i32, 90, 180] {
        header.extend_from_slice(&d.to_le_bytes());
    }
    let endless = header.as_slice().chain(std::io::repeat(0));
    let counted = CountingReader(endless, 0);
    let mut counted = counted;
    let m = MerlBrdf::read(&mut counted).unwrap_err().to_string();
    assert!(
        m.contains("after the blue block") || m.contains("trailing"),
        "{m}"
    );
    assert_eq!(counted.1, 12 + 3 * 90 * 90 * 180 * 8 + 1);
}

struct CountingReader<R>(R, usize);

impl<R: Read> Read for CountingReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.0.read(buf)?;
        self.1 += n;
        Ok(n)
    }
}

/// A named pipe with no writer given where a file is read (a table, a material, a
/// microcylinder file, a MERL file) is refused as not a regular file at once: opening it
/// would block until a writer came, forever.
#[cfg(unix)]
#[test]
fn a_named_pipe_is_refused_not_waited_on() {
    use std::path::PathBuf;
    use std::sync::mpsc;
    use std::time::Duration;
    let dir = std::env::temp_dir().join(format!("woven-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("pipe");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    type Reader = fn(&PathBuf) -> Option<Error>;
    let readers: [(&str, Reader); 4] = [
        ("Table::load", |p| Table::load(p).err()),
        ("Material::from_path", |p| Material::from_path(p).err()),
        ("Microcylinder::from_path", |p| {
            woven::microcylinder::Microcylinder::from_path(p).err()
        }),
        ("MerlBrdf::load", |p| MerlBrdf::load(p).err()),
    ];
    for (name, read) in readers {
        let (send, receive) = mpsc::channel();
        let path = fifo.clone();
        std::thread::spawn(move || send.send(read(&path).map(|e| e.to_string())));
        let message = receive
            .recv_timeout(Duration::from_secs(10))
            .unwrap_or_else(|_| panic!("{name} blocked on a named pipe"))
            .unwrap_or_else(|| panic!("{name} read a named pipe"));
        assert!(
            message.contains("a named pipe, not a regular file"),
            "{name}: {message}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
