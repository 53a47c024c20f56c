//! A reader for Weaving Information Files (WIF 1.1), the INI-like exchange format of loom drafts.
//!
//! Only what fixes the interlacing is read (threading, tie-up, treadling or lift plan, shed
//! direction, thread counts); colours, spacing and text are skipped. See
//! [`Pattern::from_wif_str`] for the rules.

use super::pattern::{Pattern, MAX_THREADS};
use crate::error::{Error, Result};
use std::fmt::Display;

/// The sections whose lines are checked and kept; lines of any other section are skipped unread.
const KNOWN: [&str; 9] = [
    "WIF",
    "CONTENTS",
    "WEAVING",
    "WARP",
    "WEFT",
    "THREADING",
    "TIEUP",
    "TREADLING",
    "LIFTPLAN",
];

/// One `key=value` line.
struct Entry<'a> {
    /// 1-based line number in the text.
    line: usize,
    /// The key, lower-cased, inner whitespace collapsed to one space (`rising shed`).
    key: String,
    /// The value, trimmed, comment removed.
    value: &'a str,
}

/// One known section and its entries, in file order.
struct Section<'a> {
    /// Upper-case name, one of [`KNOWN`].
    name: &'static str,
    /// 1-based line number of the `[NAME]` header.
    line: usize,
    entries: Vec<Entry<'a>>,
}

impl Section<'_> {
    /// The entry with this (normalised) key.
    fn get(&self, key: &str) -> Option<&Entry<'_>> {
        self.entries.iter().find(|e| e.key == key)
    }
}

/// The sections of one WIF text, with the origin for error messages.
struct Wif<'a> {
    origin: &'a str,
    sections: Vec<Section<'a>>,
}

/// Where in the file: `line 12, section [TIEUP]`.
fn at(line: usize, section: &str) -> String {
    format!("line {line}, section [{section}]")
}

/// A key as compared: lower case, runs of whitespace as one space.
fn normalise_key(key: &str) -> String {
    key.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_lowercase()
}

impl<'a> Wif<'a> {
    /// An [`Error::Parse`] for this file.
    fn error(&self, message: impl Display) -> Error {
        Error::Parse {
            path: self.origin.to_owned(),
            message: message.to_string(),
        }
    }

    /// Splits the text into its known sections, checking each of their lines.
    fn split(text: &'a str, origin: &'a str) -> Result<Wif<'a>> {
        let mut wif = Wif {
            origin,
            sections: Vec::new(),
        };
        // `None` before the first header; `Some(None)` inside a section that is skipped.
        let mut current: Option<Option<usize>> = None;
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            // Everything after `;` is a comment (the values read here never contain one).
            let content = raw.split(';').next().unwrap_or_default().trim();
            if content.is_empty() {
                continue;
            }

            // A section header `[NAME]`.
            if let Some(rest) = content.strip_prefix('[') {
                let Some(name) = rest.strip_suffix(']') else {
                    // The line is not echoed: the file may not be a WIF at all.
                    return Err(wif.error(format!(
                        "line {line}: malformed section header: expected `[NAME]`"
                    )));
                };
                let name = name.trim().to_ascii_uppercase();
                current = Some(match KNOWN.iter().find(|&&k| k == name) {
                    Some(&known) => {
                        if let Some(first) = wif.section(known) {
                            return Err(wif.error(format!(
                                "{}: duplicate section (first at line {})",
                                at(line, known),
                                first.line
                            )));
                        }
                        wif.sections.push(Section {
                            name: known,
                            line,
                            entries: Vec::new(),
                        });
                        Some(wif.sections.len() - 1)
                    }
                    None => None,
                });
                continue;
            }

            // A `key=value` line of a known section.
            let index = match current {
                None => {
                    // The line is not echoed: whatever file this is, its text stays private.
                    return Err(wif.error(format!(
                        "line {line}: text before the first section header: expected a weaving \
                         information file (WIF), which starts with a section such as `[WIF]`"
                    )));
                }
                Some(None) => continue,
                Some(Some(index)) => index,
            };
            let section = wif.sections[index].name;
            let (key, value) = match content.split_once('=') {
                Some((key, value)) if !key.trim().is_empty() => (normalise_key(key), value.trim()),
                _ => {
                    return Err(wif.error(format!(
                        "{}: malformed line `{}`: expected `key=value`",
                        at(line, section),
                        abbreviate(content)
                    )))
                }
            };
            if let Some(first) = wif.sections[index].get(&key) {
                return Err(wif.error(format!(
                    "{}: duplicate key `{key}` (first at line {})",
                    at(line, section),
                    first.line
                )));
            }
            wif.sections[index].entries.push(Entry { line, key, value });
        }
        Ok(wif)
    }

    /// The section with this upper-case name, if present.
    fn section(&self, name: &str) -> Option<&Section<'a>> {
        self.sections.iter().find(|s| s.name == name)
    }

    /// A whole number in `1..=max`, the value of `entry` in `section`; `what` names it.
    fn count(&self, section: &str, entry: &Entry<'_>, what: &str, max: usize) -> Result<usize> {
        let where_ = at(entry.line, section);
        let n: usize = entry.value.parse().map_err(|_| {
            self.error(format!(
                "{where_}: {what} `{}` is not a whole number",
                entry.value
            ))
        })?;
        if n == 0 || n > max {
            return Err(self.error(format!(
                "{where_}: {what} {n} out of range: expected 1 to {max}"
            )));
        }
        Ok(n)
    }

    /// An optional count `key` of `section` (e.g. `[WEAVING] Shafts=`), in `1..=MAX_THREADS`.
    fn optional_count(&self, section: &str, key: &str, what: &str) -> Result<Option<usize>> {
        match self.section(section).and_then(|s| s.get(key)) {
            Some(entry) => self.count(section, entry, what, MAX_THREADS).map(Some),
            None => Ok(None),
        }
    }

    /// A numbered list section: `index=n1,n2,…`. Indices must lie in `1..=max_index` and list
    /// items in `1..=max_item` (declared counts, or [`MAX_THREADS`]); `index_what`/`item_what`
    /// name them and `*_declared` says whether the bound came from the file.
    fn index_lists(
        &self,
        section: &Section<'_>,
        (index_what, max_index, index_declared): (&str, usize, bool),
        (item_what, max_item, item_declared): (&str, usize, bool),
    ) -> Result<Vec<(usize, Vec<usize>)>> {
        let bound = |what: &str, max: usize, declared: bool| {
            if declared {
                format!("{what}s are numbered 1 to {max} here")
            } else {
                format!("{what}s are numbered 1 to at most {max}")
            }
        };
        let mut out = Vec::with_capacity(section.entries.len());
        // The line of each index seen so far: `1=` and `01=` name the same end.
        let mut seen: Vec<Option<(usize, &str)>> = Vec::new();
        for entry in &section.entries {
            let where_ = at(entry.line, section.name);
            let number = |text: &str, what: &str, max: usize, declared: bool| -> Result<usize> {
                let n: usize = text.parse().map_err(|_| {
                    self.error(format!("{where_}: {what} `{text}` is not a whole number"))
                })?;
                if n == 0 || n > max {
                    return Err(self.error(format!(
                        "{where_}: {what} {n} out of range: {}",
                        bound(what, max, declared)
                    )));
                }
                Ok(n)
            };
            let index = number(&entry.key, index_what, max_index, index_declared)?;
            if seen.len() <= index {
                seen.resize(index + 1, None);
            }
            if let Some((first, key)) = seen[index] {
                return Err(self.error(format!(
                    "{where_}: key `{}` is {index_what} {index} again (first at line {first} as \
                     `{key}`)",
                    entry.key
                )));
            }
            seen[index] = Some((entry.line, &entry.key));
            // Empty items (`1=` or `1=2,,3`) name nothing.
            let items = entry
                .value
                .split(',')
                .map(str::trim)
                .filter(|item| !item.is_empty())
                .map(|item| number(item, item_what, max_item, item_declared))
                .collect::<Result<Vec<_>>>()?;
            out.push((index, items));
        }
        Ok(out)
    }

    /// A missing-section error.
    fn missing(&self, what: &str) -> Error {
        self.error(format!("missing section {what}"))
    }
}

/// Parses a WIF text into the drafted pattern (all ends × all picks); see
/// [`Pattern::from_wif_str`].
pub(crate) fn parse(text: &str, origin: &str) -> Result<Pattern> {
    let wif = Wif::split(text, origin)?;
    if wif.section("WIF").is_none() {
        return Err(wif.missing("[WIF] (is this a weaving information file?)"));
    }
    let threading = wif
        .section("THREADING")
        .ok_or_else(|| wif.missing("[THREADING]"))?;

    // Declared sizes and the shed direction.
    let shafts = wif.optional_count("WEAVING", "shafts", "Shafts")?;
    let treadles = wif.optional_count("WEAVING", "treadles", "Treadles")?;
    let declared_ends = wif.optional_count("WARP", "threads", "Threads")?;
    let declared_picks = wif.optional_count("WEFT", "threads", "Threads")?;
    let rising = match wif.section("WEAVING").and_then(|s| s.get("rising shed")) {
        None => true,
        Some(entry) => match entry.value.to_ascii_lowercase().as_str() {
            "yes" | "true" | "1" | "on" => true,
            "no" | "false" | "0" | "off" => false,
            other => {
                return Err(wif.error(format!(
                    "{}: Rising Shed `{other}` is not a boolean: expected yes or no",
                    at(entry.line, "WEAVING")
                )))
            }
        },
    };
    let bound = |declared: Option<usize>| (declared.unwrap_or(MAX_THREADS), declared.is_some());
    let (max_shaft, shafts_declared) = bound(shafts);
    let (max_treadle, treadles_declared) = bound(treadles);
    let (max_end, ends_declared) = bound(declared_ends);
    let (max_pick, picks_declared) = bound(declared_picks);
    let shaft = ("shaft", max_shaft, shafts_declared);
    let treadle = ("treadle", max_treadle, treadles_declared);
    let end = ("end", max_end, ends_declared);
    let pick = ("pick", max_pick, picks_declared);

    // Threading: end → shafts.
    let threading_lists = wif.index_lists(threading, end, shaft)?;

    // Pick → lifted (or, with a sinking shed, lowered) shafts: from treadling and tie-up, or
    // from the lift plan; a file with both would leave one of them unread.
    let lifts = match (wif.section("TIEUP"), wif.section("TREADLING")) {
        (Some(tieup), Some(treadling)) => {
            if let Some(liftplan) = wif.section("LIFTPLAN") {
                return Err(wif.error(format!(
                    "{}: a lift plan beside [TIEUP] and [TREADLING]: both say which shafts each \
                     pick lifts; keep one of them",
                    at(liftplan.line, "LIFTPLAN")
                )));
            }
            let mut by_treadle: Vec<Shafts> = Vec::new();
            for (t, shafts) in wif.index_lists(tieup, treadle, shaft)? {
                if by_treadle.len() <= t {
                    by_treadle.resize(t + 1, Shafts::default());
                }
                by_treadle[t] = Shafts::from_list(&shafts);
            }
            wif.index_lists(treadling, pick, treadle)?
                .into_iter()
                .map(|(p, ts)| {
                    // A treadle without a tie-up entry lifts nothing; a treadle named twice lifts
                    // its shafts once (a union of sets, so that no list grows with repeats).
                    let mut shafts = Shafts::default();
                    for t in ts {
                        if let Some(tied) = by_treadle.get(t) {
                            shafts.union_with(tied);
                        }
                    }
                    (p, shafts)
                })
                .collect::<Vec<_>>()
        }
        (tieup, treadling) => match wif.section("LIFTPLAN") {
            Some(liftplan) => wif
                .index_lists(liftplan, pick, shaft)?
                .into_iter()
                .map(|(p, shafts)| (p, Shafts::from_list(&shafts)))
                .collect(),
            None => {
                return Err(wif.missing(match (tieup, treadling) {
                    (Some(_), None) => "[TREADLING] (needed with [TIEUP]), or [LIFTPLAN]",
                    (None, Some(_)) => "[TIEUP] (needed with [TREADLING]), or [LIFTPLAN]",
                    _ => "[TIEUP] and [TREADLING], or [LIFTPLAN]",
                }))
            }
        },
    };

    // Sizes: declared, else the largest index seen.
    let ends = declared_ends
        .or_else(|| threading_lists.iter().map(|(e, _)| *e).max())
        .ok_or_else(|| {
            wif.error(format!(
                "{}: no warp ends: the section is empty and [WARP] Threads= is absent",
                at(threading.line, "THREADING")
            ))
        })?;
    let picks = declared_picks
        .or_else(|| lifts.iter().map(|(p, _)| *p).max())
        .ok_or_else(|| {
            wif.error(
                "no weft picks: the treadling or lift plan is empty and [WEFT] Threads= is absent",
            )
        })?;

    // Tables indexed from 1 (index 0 unused): the shafts of each end, the shafts marked on
    // each pick, as bit sets (memory and time bounded by ends · picks · shafts / 64).
    let mut end_shafts = vec![Shafts::default(); ends + 1];
    for (e, shafts) in threading_lists {
        end_shafts[e] = Shafts::from_list(&shafts);
    }
    let mut marked = vec![Shafts::default(); picks + 1];
    for (p, shafts) in lifts {
        marked[p] = shafts;
    }

    // A marked shaft is lifted on a rising shed (warp on top) and lowered on a sinking one
    // (weft on top); an end on no shaft is never marked.
    Ok(Pattern::from_fn(picks, ends, |r, c| {
        let is_marked = end_shafts[c + 1].intersects(&marked[r + 1]);
        is_marked != rising
    }))
}

/// A set of shafts (numbers `1..=MAX_THREADS`) as bits.
#[derive(Clone, Debug, Default)]
struct Shafts(Vec<u64>);

impl Shafts {
    fn from_list(shafts: &[usize]) -> Shafts {
        let mut set = Shafts::default();
        for &s in shafts {
            if set.0.len() <= s / 64 {
                set.0.resize(s / 64 + 1, 0);
            }
            set.0[s / 64] |= 1 << (s % 64);
        }
        set
    }

    fn union_with(&mut self, other: &Shafts) {
        if self.0.len() < other.0.len() {
            self.0.resize(other.0.len(), 0);
        }
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            *a |= b;
        }
    }

    fn intersects(&self, other: &Shafts) -> bool {
        self.0.iter().zip(&other.0).any(|(a, b)| a & b != 0)
    }
}

/// At most 40 characters of `s`, marked with `…` where cut.
fn abbreviate(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str) -> String {
        match parse(text, "<test>") {
            Err(Error::Parse { path, message }) => {
                assert_eq!(path, "<test>");
                message
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    const PLAIN: &str = "[WIF]\n[THREADING]\n1=1\n2=2\n[TIEUP]\n1=1\n2=2\n[TREADLING]\n1=1\n2=2\n";

    #[test]
    fn keys_are_normalised() {
        assert_eq!(normalise_key("  Rising   Shed "), "rising shed");
        assert_eq!(normalise_key("THREADS"), "threads");
    }

    #[test]
    fn minimal_plain() {
        let p = parse(PLAIN, "<test>").unwrap();
        assert_eq!(p.to_matrix(), vec![vec![0, 1], vec![1, 0]]);
    }

    #[test]
    fn byte_order_mark_crlf_and_comments() {
        let text = format!(
            "\u{feff}; a comment\r\n{}",
            PLAIN.replace('\n', " ; trailing\r\n")
        );
        let p = parse(&text, "<test>").unwrap();
        assert_eq!(p.to_matrix(), vec![vec![0, 1], vec![1, 0]]);
    }

    #[test]
    fn unknown_sections_are_skipped() {
        let text = format!("{PLAIN}[COLOR TABLE]\nthis line is not key=value\n[NOTES]\n1=x\n");
        assert!(parse(&text, "<test>").is_ok());
    }

    #[test]
    fn errors_name_line_and_section() {
        let m = message("[WIF]\n[THREADING]\n1=1\nnonsense\n");
        assert!(m.contains("line 4") && m.contains("[THREADING]"), "{m}");
        let m = message("Version=1.1\n[WIF]\n");
        assert!(
            m.contains("line 1") && m.contains("before the first section"),
            "{m}"
        );
        let m = message("[WIF\n");
        assert!(m.contains("line 1") && m.contains("section header"), "{m}");
        let m = message(&format!("{PLAIN}[TIEUP]\n"));
        assert!(
            m.contains("line 11") && m.contains("duplicate section"),
            "{m}"
        );
        let m = message("[WIF]\n[THREADING]\n1=1\n1=2\n");
        assert!(m.contains("line 4") && m.contains("duplicate key"), "{m}");
        let m = message(&PLAIN.replace("2=2\n[TIEUP]", "0=2\n[TIEUP]"));
        assert!(
            m.contains("line 4") && m.contains("end 0 out of range"),
            "{m}"
        );
        let m = message(&PLAIN.replace("[WIF]", "[WIF]\n[WEAVING]\nRising Shed=maybe"));
        assert!(m.contains("line 3") && m.contains("[WEAVING]"), "{m}");
    }

    #[test]
    fn missing_sections() {
        assert!(message("[THREADING]\n1=1\n").contains("missing section [WIF]"));
        assert!(message("[WIF]\n[TIEUP]\n1=1\n").contains("missing section [THREADING]"));
        let m = message("[WIF]\n[THREADING]\n1=1\n[TIEUP]\n1=1\n");
        assert!(m.contains("missing section [TREADLING]"), "{m}");
        let m = message("[WIF]\n[THREADING]\n1=1\n");
        assert!(m.contains("[LIFTPLAN]"), "{m}");
    }

    #[test]
    fn empty_threading_and_treadling() {
        let m = message("[WIF]\n[THREADING]\n[LIFTPLAN]\n1=1\n");
        assert!(m.contains("line 2") && m.contains("no warp ends"), "{m}");
        let m = message("[WIF]\n[THREADING]\n1=1\n[LIFTPLAN]\n");
        assert!(m.contains("no weft picks"), "{m}");
    }

    #[test]
    fn too_many_threads() {
        let m = message(&format!("{PLAIN}[WARP]\nThreads=5000\n"));
        assert!(m.contains("line 12") && m.contains("out of range"), "{m}");
        let m = message("[WIF]\n[THREADING]\n99999=1\n[LIFTPLAN]\n1=1\n");
        assert!(m.contains("line 3") && m.contains("end 99999"), "{m}");
    }
}
