//! The catalogue of real measurements in the repository's `data/` folder (data/README.md): what
//! the fitter's sweep and the tests iterate over.

use super::curet;
use super::{load, DataError, Dataset, Format};
use std::path::PathBuf;

/// Where a bundled dataset comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Family {
    /// CUReT (Dana et al. 1999): 205 goniometric measurements per sample, averaged over R, G, B,
    /// relatively calibrated.
    Curet,
    /// RGL/EPFL acrylic felts (Dupuy & Jakob 2018), evaluated with RGL's reference loader on a
    /// dense grid: measured data, RGB, absolute.
    RglFelt,
    /// RGL/EPFL acrylic felts of which only the NBRDF neural fit (Sztrajman et al. 2021) is at
    /// hand, evaluated on the same grid.
    RglNbrdf,
    /// MERL BRDFs (Matusik et al. 2003) of fabrics, as their NBRDF fits on the grid; MERL data is
    /// CC-BY-SA 4.0. Published SGD and ABC fits exist for each ([`super::published`]).
    Merl,
    /// DTU's `greencloth` (Nielsen et al. 2015, MERL format), as its NBRDF fit on the grid.
    Nielsen,
}

impl Family {
    /// A short name: `curet`, `rgl`, `rgl-nbrdf`, `merl`, `dtu`.
    pub fn name(self) -> &'static str {
        match self {
            Family::Curet => "curet",
            Family::RglFelt => "rgl",
            Family::RglNbrdf => "rgl-nbrdf",
            Family::Merl => "merl",
            Family::Nielsen => "dtu",
        }
    }
}

/// One real dataset in `data/`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bundled {
    /// The dataset's name, as [`Bundled::load`] names it (`curet-44-linen`, `beige-fabric`, …).
    pub name: String,
    /// Where it comes from.
    pub family: Family,
    /// The file, relative to [`data_dir`].
    pub file: &'static str,
    /// The material's selector in a file of several (CUReT), else `None`.
    pub selector: Option<String>,
    /// The reader.
    pub format: Format,
    /// Whether the material is a textile (MERL's `nylon` sheet and `green-latex` are not).
    pub textile: bool,
    /// Whether the values are relatively calibrated.
    pub relative: bool,
    /// The number of rows above the horizon ([`Bundled::load`] gives exactly this many samples).
    pub samples: usize,
}

impl Bundled {
    /// The file's path.
    pub fn path(&self) -> PathBuf {
        data_dir().join(self.file)
    }

    /// What [`load`] takes: the path, with `#SELECTOR` where the file holds several materials.
    pub fn spec(&self) -> PathBuf {
        let mut s = self.path().into_os_string();
        if let Some(sel) = &self.selector {
            s.push("#");
            s.push(sel);
        }
        PathBuf::from(s)
    }

    /// The NBRDF network the grid was made from (`*.nbrdf.json` beside it), for the families
    /// known through one (MERL, DTU, the RGL felts without a `.bsdf`): evaluate it at any
    /// directions with [`super::nbrdf::Nbrdf`].
    pub fn network(&self) -> Option<PathBuf> {
        match self.family {
            Family::Merl | Family::Nielsen | Family::RglNbrdf => self
                .file
                .strip_suffix(".grid.csv")
                .map(|stem| data_dir().join(format!("{stem}.nbrdf.json"))),
            Family::Curet | Family::RglFelt => None,
        }
    }

    /// Reads the dataset.
    ///
    /// # Errors
    /// As [`load`] (only if `data/` was changed or is missing).
    pub fn load(&self) -> Result<Dataset, DataError> {
        load(&self.spec())
    }
}

/// The repository's `data/` folder (found from this crate's source location at build time).
pub fn data_dir() -> PathBuf {
    let krate = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    // crates/woven-fit → the repository's root.
    match krate.parent().and_then(|crates| crates.parent()) {
        Some(root) => root.join("data"),
        None => krate.join("../../data"),
    }
}

/// The MERL materials with NBRDF grids in `data/merl/`: name, file, whether a textile.
const MERL: [(&str, &str, bool); 15] = [
    ("beige-fabric", "merl/beige-fabric.grid.csv", true),
    ("black-fabric", "merl/black-fabric.grid.csv", true),
    ("blue-fabric", "merl/blue-fabric.grid.csv", true),
    (
        "dark-specular-fabric",
        "merl/dark-specular-fabric.grid.csv",
        true,
    ),
    ("green-fabric", "merl/green-fabric.grid.csv", true),
    ("green-latex", "merl/green-latex.grid.csv", false),
    (
        "light-brown-fabric",
        "merl/light-brown-fabric.grid.csv",
        true,
    ),
    ("nylon", "merl/nylon.grid.csv", false),
    ("pink-fabric", "merl/pink-fabric.grid.csv", true),
    ("pink-fabric2", "merl/pink-fabric2.grid.csv", true),
    ("pink-felt", "merl/pink-felt.grid.csv", true),
    ("red-fabric", "merl/red-fabric.grid.csv", true),
    ("red-fabric2", "merl/red-fabric2.grid.csv", true),
    ("white-fabric", "merl/white-fabric.grid.csv", true),
    ("white-fabric2", "merl/white-fabric2.grid.csv", true),
];

/// The rows of a grid above the horizon: θi, θo ∈ {0, 5, …, 80}° and 13 azimuths.
const GRID_SAMPLES: usize = 17 * 17 * 13;

/// Every real dataset in `data/`: the 11 CUReT textile samples, the 3 measured RGL felts, the 3
/// RGL felts known only through their NBRDF fits, the 15 MERL materials (13 fabrics, a nylon
/// sheet and green latex) and DTU's green cloth — 33 in all.
pub fn bundled() -> Vec<Bundled> {
    let mut out = Vec::new();
    for (number, name) in curet::TEXTILES {
        out.push(Bundled {
            name: curet::dataset_name(number),
            family: Family::Curet,
            file: "curet/abrdf.dat",
            selector: Some(name.to_string()),
            format: Format::CuretDat,
            textile: true,
            relative: true,
            samples: curet::MEASUREMENTS,
        });
    }
    let grid = |name: &str, family, file: &'static str, textile| Bundled {
        name: name.to_string(),
        family,
        file,
        selector: None,
        format: Format::Grid,
        textile,
        relative: false,
        samples: GRID_SAMPLES,
    };
    out.push(grid(
        "acrylic_felt_pink_rgb",
        Family::RglFelt,
        "rgl/acrylic_felt_pink_rgb.grid.csv",
        true,
    ));
    out.push(grid(
        "acrylic_felt_purple_rgb",
        Family::RglFelt,
        "rgl/acrylic_felt_purple_rgb.grid.csv",
        true,
    ));
    out.push(grid(
        "acrylic_felt_white_rgb",
        Family::RglFelt,
        "rgl/acrylic_felt_white_rgb.grid.csv",
        true,
    ));
    out.push(grid(
        "acrylic_felt_green_rgb",
        Family::RglNbrdf,
        "nbrdf-rgl/acrylic_felt_green_rgb.grid.csv",
        true,
    ));
    out.push(grid(
        "acrylic_felt_orange_rgb",
        Family::RglNbrdf,
        "nbrdf-rgl/acrylic_felt_orange_rgb.grid.csv",
        true,
    ));
    out.push(grid(
        "acrylic_felt_yellow_rgb",
        Family::RglNbrdf,
        "nbrdf-rgl/acrylic_felt_yellow_rgb.grid.csv",
        true,
    ));
    for (name, file, textile) in MERL {
        out.push(grid(name, Family::Merl, file, textile));
    }
    out.push(grid(
        "greencloth",
        Family::Nielsen,
        "nielsen/greencloth.grid.csv",
        true,
    ));
    out
}
