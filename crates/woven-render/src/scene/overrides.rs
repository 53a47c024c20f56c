//! What a front end may change in a checked scene ([`FilmOverrides`]), and the one door it
//! changes it through ([`SceneDescription::with_overrides`]), checked against the scene file's
//! own limits: `woven render`'s flags, `woven.render`'s and `woven.portable_scene`'s arguments.

use super::{SceneDescription, MAX_EXPOSURE, MAX_FILM_SIDE, MAX_SPP};
use crate::rng::SamplerKind;
use crate::tonemap::ToneMap;
use crate::{Error, Result};

/// Changes to a scene's `[film]`; `None` keeps the scene's own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FilmOverrides {
    /// `film.spp`, in `[1, MAX_SPP]`.
    pub spp: Option<usize>,
    /// `film.width`, pixels in `[1, MAX_FILM_SIDE]`.
    pub width: Option<usize>,
    /// `film.height`, pixels in `[1, MAX_FILM_SIDE]`.
    pub height: Option<usize>,
    /// `film.seed`.
    pub seed: Option<u64>,
    /// `film.sampler`.
    pub sampler: Option<SamplerKind>,
    /// `film.exposure`, stops in `[-MAX_EXPOSURE, MAX_EXPOSURE]`.
    pub exposure: Option<f64>,
    /// `film.tonemap`.
    pub tonemap: Option<ToneMap>,
    /// `film.denoise`.
    pub denoise: Option<bool>,
}

impl SceneDescription {
    /// This scene with `overrides` applied: the one door through which a front end changes a
    /// checked scene.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] naming the film key (`film.width`), the value and the range the
    /// scene file states for it.
    pub fn with_overrides(mut self, overrides: &FilmOverrides) -> Result<SceneDescription> {
        let count = |name: &str, value: Option<usize>, max: usize| match value {
            Some(v) if !(1..=max).contains(&v) => Err(Error::InvalidSetting {
                name: name.into(),
                value: v.to_string(),
                expected: format!("in [1, {max}]"),
            }),
            _ => Ok(value),
        };
        let film = &mut self.film;
        if let Some(n) = count("film.spp", overrides.spp, MAX_SPP)? {
            film.spp = n;
        }
        if let Some(w) = count("film.width", overrides.width, MAX_FILM_SIDE)? {
            film.width = w;
        }
        if let Some(h) = count("film.height", overrides.height, MAX_FILM_SIDE)? {
            film.height = h;
        }
        if let Some(ev) = overrides.exposure {
            if !(ev.is_finite() && ev.abs() <= MAX_EXPOSURE) {
                return Err(Error::InvalidSetting {
                    name: "film.exposure".into(),
                    value: ev.to_string(),
                    expected: format!("stops in [-{MAX_EXPOSURE}, {MAX_EXPOSURE}]"),
                });
            }
            film.display.exposure = ev;
        }
        film.seed = overrides.seed.unwrap_or(film.seed);
        film.sampler = overrides.sampler.unwrap_or(film.sampler);
        film.display.tonemap = overrides.tonemap.unwrap_or(film.display.tonemap);
        film.denoise = overrides.denoise.unwrap_or(film.denoise);
        Ok(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SHOWCASE_SCENE;
    use std::path::Path;

    fn showcase() -> SceneDescription {
        SceneDescription::from_str(SHOWCASE_SCENE, "<showcase>", Path::new(".")).unwrap()
    }

    #[test]
    fn overrides_apply_within_the_scene_files_limits() {
        let o = FilmOverrides {
            spp: Some(3),
            width: Some(64),
            height: Some(36),
            seed: Some(9),
            exposure: Some(-1.5),
            denoise: Some(false),
            ..FilmOverrides::default()
        };
        let d = showcase().with_overrides(&o).unwrap();
        let f = &d.film;
        assert_eq!((f.spp, f.width, f.height, f.seed), (3, 64, 36, 9));
        assert_eq!((f.display.exposure, f.denoise), (-1.5, false));
        let same = showcase()
            .with_overrides(&FilmOverrides::default())
            .unwrap();
        assert_eq!(same.film, showcase().film);
        for (bad, key) in [
            (
                FilmOverrides {
                    width: Some(0),
                    ..o
                },
                "film.width",
            ),
            (
                FilmOverrides {
                    height: Some(MAX_FILM_SIDE + 1),
                    ..o
                },
                "film.height",
            ),
            (
                FilmOverrides {
                    spp: Some(MAX_SPP + 1),
                    ..o
                },
                "film.spp",
            ),
            (
                FilmOverrides {
                    exposure: Some(f64::NAN),
                    ..o
                },
                "film.exposure",
            ),
        ] {
            let Err(Error::InvalidSetting { name, .. }) = showcase().with_overrides(&bad) else {
                panic!("{bad:?} accepted");
            };
            assert_eq!(name, key);
        }
    }
}
