//! Built models, kept for the next request: a click on the hemisphere asks for the same material
//! again, and a slider of `[yarn]` or `[weave]` leaves the fiber — whose β table (docs/spec.md
//! §1.5) is most of the cost of building a model — as it was.
//!
//! [`ModelCache::build`] composes fiber → yarn → weave as [`Material::build`] does (a test checks
//! that the two agree), with the fiber from the cache when its parameters and wavelength match.

use std::sync::{Arc, Mutex};
use woven::fiber::Fiber;
use woven::material::Material;
use woven::{Model, Result};

/// Models kept (most recent first).
const MODELS: usize = 4;
/// Fibers kept (most recent first).
const FIBERS: usize = 8;

/// Recently built models and fibers.
#[derive(Default)]
pub struct ModelCache {
    models: Mutex<Vec<(String, Arc<Model>)>>,
    fibers: Mutex<Vec<(String, Fiber)>>,
}

/// Looks `key` up in a most-recent-first list, moving a hit to the front.
fn lookup<T: Clone>(list: &Mutex<Vec<(String, T)>>, key: &str) -> Option<T> {
    let mut list = list.lock().unwrap_or_else(|e| e.into_inner());
    let i = list.iter().position(|(k, _)| k == key)?;
    let entry = list.remove(i);
    let value = entry.1.clone();
    list.insert(0, entry);
    Some(value)
}

/// Puts `key` at the front of a list of at most `cap` entries.
fn remember<T>(list: &Mutex<Vec<(String, T)>>, key: String, value: T, cap: usize) {
    let mut list = list.lock().unwrap_or_else(|e| e.into_inner());
    list.retain(|(k, _)| *k != key);
    list.insert(0, (key, value));
    list.truncate(cap);
}

impl ModelCache {
    /// `material` prepared at `wavelength_nm`, as [`Material::build`] prepares it.
    ///
    /// # Errors
    /// As [`Material::build`].
    pub fn build(&self, material: &Material, wavelength_nm: f64) -> Result<Arc<Model>> {
        let key = format!(
            "{wavelength_nm:?}\n{}",
            material.to_self_contained_toml_string()
        );
        if let Some(m) = lookup(&self.models, &key) {
            return Ok(m);
        }
        material.validate()?;
        let fiber_key = format!("{wavelength_nm:?}\n{:?}", material.fiber);
        let fiber = match lookup(&self.fibers, &fiber_key) {
            Some(f) => f,
            None => {
                let f = Fiber::new(&material.fiber, wavelength_nm)?;
                remember(&self.fibers, fiber_key, f.clone(), FIBERS);
                f
            }
        };
        let model = Arc::new(material.build_with(fiber)?);
        remember(&self.models, key, model.clone(), MODELS);
        Ok(model)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use woven::Vec3;

    #[test]
    fn cached_models_are_the_library_s() {
        let cache = ModelCache::default();
        for name in Material::preset_names() {
            let mut m = Material::preset(name).unwrap();
            for step in 0..2 {
                // The second time, another yarn on the cached fiber.
                if step == 1 {
                    m.yarn.as_mut().unwrap().slope_std *= 0.5;
                }
                let want = m.build(550.0).unwrap();
                let got = cache.build(&m, 550.0).unwrap();
                let again = cache.build(&m, 550.0).unwrap();
                assert!(Arc::ptr_eq(&got, &again));
                for (ti, pi, tr, pr) in [
                    (0.3, 0.0, 0.5, 3.0),
                    (0.9, 1.0, 0.4, 4.5),
                    (1.2, 2.0, 0.8, 0.3),
                ] {
                    let (s, v) = (Vec3::from_spherical(ti, pi), Vec3::from_spherical(tr, pr));
                    assert_eq!(got.eval(s, v), want.eval(s, v), "{name}, step {step}");
                }
            }
        }
        assert!(cache
            .build(&Material::preset("silk").unwrap(), 50.0)
            .is_err());
    }
}
