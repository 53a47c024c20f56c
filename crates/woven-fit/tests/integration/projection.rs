//! A woven yarn projected onto the standard lobes (`woven_fit::projection`): the sheen, Lambert
//! and anisotropic GGX carry it better than one isotropic GGX + Lambert, and the GGX stretches
//! its highlight across the yarn, as a cylinder's reflection cone does.

use woven::material::Material;
use woven::table::{Table, TableOptions};
use woven_fit::projection::{project, LobeSet, Reference};

#[test]
fn a_woven_yarn_projects_onto_the_fabric_lobes_better_than_onto_one_ggx() {
    // The sateen's yarn on a small table: its BRDF to the table's accuracy, in seconds.
    let m = Material::preset("polyester-sateen").unwrap().yarn_family();
    let options = TableOptions {
        n_theta: 12,
        n_phi: 8,
        n_h: 31,
        ..TableOptions::default()
    };
    let table = Table::build(&m.build(550.0).unwrap(), &m, &options, &|_, _| {}).unwrap();
    let reference = Reference::sample(|wi, wo| table.eval(wi, wo));
    let mixture = project(&reference, LobeSet::Fabric).unwrap();
    let iso = project(&reference, LobeSet::IsotropicGgx).unwrap();
    eprintln!(
        "sateen yarn: mixture {:.3} ({}), isotropic GGX + Lambert {:.3}",
        mixture.rms_log,
        mixture.lobes.describe(),
        iso.rms_log
    );
    // Measured here 0.114 against 0.345; on the exact model (examples/projection.rs) 0.121
    // against 0.348.
    assert!(
        mixture.rms_log < 0.5 * iso.rms_log,
        "{} {}",
        mixture.rms_log,
        iso.rms_log
    );
    let [along, across] = mixture.lobes.alpha;
    assert!(along < 0.5 * across, "α along {along}, across {across}");
}
