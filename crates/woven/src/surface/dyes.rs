//! A surface's dyes: the material's own albedos (what dyes replace), the weft's and the warp's
//! dyed albedos per channel, and how unevenly each yarn is dyed along its length.

use super::Irregularity;
use crate::color::Rgb;
use crate::table::{Albedos, DyeRule};

/// The dyes of a [`WovenSurface`](super::WovenSurface).
#[derive(Clone, Debug)]
pub(super) struct Dyes {
    /// The material's own albedos (what dyes replace).
    pub(super) own: Albedos,
    /// The weft's dyed albedos per channel.
    pub(super) weft: [Albedos; 3],
    /// The warp's dyed albedos per channel.
    pub(super) warp: [Albedos; 3],
    /// How unevenly each yarn is dyed along its length.
    pub(super) irregularity: Irregularity,
}

impl Dyes {
    /// `own` dyed `weft` and `warp` (`None`: its own), unevenly by `irregularity`.
    pub(super) fn new(
        own: Albedos,
        [weft, warp]: [Option<Rgb>; 2],
        irregularity: Irregularity,
    ) -> Dyes {
        Dyes {
            own,
            weft: own.dyed(weft),
            warp: own.dyed(warp),
            irregularity,
        }
    }

    /// The albedos per channel of the weft (`warp = false`) or the warp.
    pub(super) fn albedos(&self, warp: bool) -> &[Albedos; 3] {
        if warp {
            &self.warp
        } else {
            &self.weft
        }
    }

    /// The dye rule of the own albedos ([`Albedos::dye_rule`]).
    pub(super) fn rule(&self) -> DyeRule {
        self.own.dye_rule()
    }
}
