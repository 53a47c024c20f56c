"""The woven cloth BSDF for Mitsuba 3: ``woven.mitsuba.register()``, then ``type = "woven"``.

    import mitsuba as mi, woven.mitsuba
    mi.set_variant("llvm_ad_rgb")
    woven.mitsuba.register()
    bsdf = mi.load_dict({"type": "woven", "material": "polyester-sateen", "pattern": "twill-2/1",
                         "weft_color": {"type": "rgb", "value": [0.6, 0.1, 0.1]}})

**Keys.** The plugin takes the surface keys of ``woven render``'s scenes and ``woven.Surface``
with the same names, meanings, ranges and defaults: the library owns them
(``woven.SURFACE_KEYS``; the table in docs/python.md), and a key not given here is not given to
``woven.Surface``, so the same keys give the same surface everywhere. Here in particular:
``yarns_per_unit`` is one number or a string ``"n_u, n_v"``, and ``irregularity`` one number or
``"weft, warp"`` (the library reads both forms); ``weft_color`` and ``warp_color`` may be any
Mitsuba texture (read at the hit);
``footprint_filter`` is a key of the material (in scenes, of the ``[integrator]``). Beside them,
``table`` (instead of ``material``) takes a ``.wtab`` file, rendered as the BRDF it was built for
or, with ``pattern`` or ``weft_fraction``, as the yarn of a weave. A ``material``'s yarn table
comes from the table cache ``woven render`` uses, or is built there (seconds per preset).

**Footprints.** ``woven render`` knows each camera ray's footprint (its ray differentials):
``detail = "auto"`` resolves fibres where a pixel spans well under a yarn, and the footprint
filter blends toward the macro BRDF where it spans cells. Mitsuba hands a BSDF the footprint as
``si.duv_dx``, ``si.duv_dy``, which its integrators compute only for BSDFs that ask for them
(this one does, whenever ``footprint_filter`` is on and the surface uses a footprint) and only
from rays that carry differentials: ``direct`` and ``aov`` do, for camera rays (scaled by
1/√spp, as Mitsuba scales them); ``path``, ``volpath`` and ``prb`` carry none. ``register()``
therefore also registers ``woven_path``: ``path``'s estimator with the camera ray's footprint
(over a whole pixel, as ``woven render``'s) at the first vertex; use it for woven scenes. Where
the partials are zero (under ``path``, and at every later vertex) the plugin gives the library
no footprint, and the library's rule for that case holds, as at every later vertex of ``woven
render``'s paths: no filtering, and ``"auto"`` shades each point at yarn level
(docs/render.md).

**Directions.** Mitsuba's ``si.wi`` points toward the viewer (woven's ``wo``) and ``wo`` toward
the light (woven's ``wi``). ``sample`` draws the light direction for the viewer (the library's
radiance transport mode), and ``pdf`` returns that density, so the ``paper`` normalization's
missing reciprocity is handled exactly: the weight is the true f(wi, wo) cos θ / pdf.

**Variants: traced, or the library lane by lane.** Scalar variants call the library's
``woven.Surface`` for each ray. JIT variants (``llvm_*``, ``cuda_*``) trace in Dr.Jit what
Dr.Jit can gather: a surface at ``detail`` "yarns" or "cloth" without ``relief`` (and any
surface without a pattern) is the yarn table's interpolation and sampling (``JitTable``) at the lobes of each lane's
cell, float and gap (``JitLayout``, from the constants ``Surface.layout()`` hands over; the
tilted floats' geometry in ``JitFloat``, linear or shaped by ``float_crest``/``float_flank``,
from the profile's knots; each yarn's uneven dye in ``JitIrregularity``; a whole tilted float
is one look-up in its own table, ``Surface.float_table``), compiled into Mitsuba's kernels.
What the library computes and Dr.Jit does not trace — ``detail`` "auto" (the default) and
"fibers" on a pattern (the fibres' draws), ``relief`` (the weave's relief, its crowned table
and ratio), and microcylinder fabrics — the library decides (``Surface.route``, the reason why or None), and
it evaluates, samples and weighs lane by lane: each call hands the lanes' arrays to ``woven.Surface``
(rayon-parallel in Rust, the GIL released) and back, so there is one implementation of those
levels. That needs Dr.Jit's evaluated (wavefront) mode, in which a call sees its lanes' values:
``register()`` switches its thread's ``SymbolicLoops``, ``SymbolicCalls`` and
``SymbolicConditionals`` off (``register(symbolic=True)`` leaves them on, for scenes whose woven
surfaces are all traced); a library surface called from a symbolic trace raises an error saying
so. On a CUDA variant the library's lanes run on the CPU, copied over and back per call.

The traced code repeats the library's operation by operation (crates/woven/src/table/,
crates/woven/src/surface/, crates/woven/src/yarn/float.rs); tests/test_mitsuba.py pins it lane
for lane to the library's values, to the horizon, for eval, pdf and sample. It interpolates
everywhere: tables of single-orientation yarns that the library evaluates exactly for
near-forward pairs (|wi + wo| < 0.5) or half vectors within 5° of the horizon (which a tilted
frame can bring about) give ``Table.eval_interpolated`` there, and flat fiber surfaces their
table, not the exact model.

**Light through the cloth.** With ``transmission`` on (a material's ``[weave] transmission``,
such as the ``cotton-voile`` preset's, or the key) the BSDF is two-sided and has three
components, as ``woven render`` shades it: the reflection (``GlossyReflection``), the light
through the yarns (``DiffuseTransmission``: ``wo`` and ``si.wi`` on opposite sides) and the
light straight between them (``Null``: the direction goes on, the share ``Surface.pass_through``
along it, which ``eval_null_transmission`` returns). A hit from behind is shaded as the back face
(``Surface.back``: the pattern's complement), its directions turned half a turn about the weft,
(x, y, z) → (x, −y, −z), as ``woven render`` turns a hit's frame. The library answers such a
surface lane by lane in every variant (``Surface.route``). ``woven_path`` traces its shadow rays
through null components (multiplying what each passes, as ``volpath`` does), and a path that
goes straight through keeps its last vertex and depth, as in ``woven render``; Mitsuba's
``path`` stops shadow rays at the cloth, so light beyond a sheer then reaches a point only
through the BSDF's draws (unbiased, but noisier).

**Variants.** The woven cloth's values are RGB: RGB variants take it (``scalar_rgb``,
``llvm_ad_rgb``, ``cuda_ad_rgb``); spectral and monochrome variants refuse it by name, and for
them ``woven export --format rgl --spectral`` writes a file Mitsuba's ``measured`` BSDF reads.

``material`` may also name a microcylinder fabric (Sadeghi et al. 2013: a ``microcylinder-*``
preset, or a file with ``model = "microcylinder"``; see ``woven.Microcylinder``). RGB variants
then evaluate, sample and weigh it with the library (the keys above other than ``material`` do
not apply and are refused by name); spectral variants refuse it, its values being RGB.
"""

from __future__ import annotations

import woven

from ._bsdf import _bsdf_class
from ._float import JitFloat
from ._integrator import _integrator_class
from ._frames import _turn, _unturn  # noqa: F401  (the tests pin them)
from ._irregular import JitIrregularity
from ._layout import JitLayout
from ._microcylinder import _microcylinder_class
from ._surface import _evaluated_mode
from ._table import JitTable

__all__ = ["register", "JitTable", "JitLayout", "JitFloat", "JitIrregularity"]

_REGISTERED = set()


def register(symbolic=False):
    """Registers the ``woven`` BSDF and the ``woven_path`` integrator (``path`` with the camera
    ray's footprint at the first vertex) with Mitsuba for the current variant
    (``mi.set_variant`` first). Safe to call more than once.

    In a JIT variant it also switches Dr.Jit, in the calling thread, to evaluated loops, calls
    and conditionals, which the surfaces the library evaluates lane by lane need (``detail``
    "auto", the default, and "fibers" on a pattern; ``relief``; microcylinder fabrics): call it
    in the thread that renders. ``symbolic=True`` leaves Dr.Jit's modes alone, for scenes whose
    woven surfaces are all traced (``detail`` "yarns" or "cloth"): a surface that needs the
    library then raises an error naming this when it is called."""
    import drjit as dr
    import mitsuba as mi

    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant first (mi.set_variant)")
    if dr.is_jit_v(mi.Float) and not symbolic:
        _evaluated_mode(dr)
    if variant in _REGISTERED:
        return
    cls = _bsdf_class(mi)
    fabric_cls = _microcylinder_class(mi)
    mi.register_bsdf("woven", lambda props: _make(props, cls, fabric_cls))
    path_cls = _integrator_class(mi)
    mi.register_integrator("woven_path", lambda props: path_cls(props))
    _REGISTERED.add(variant)


def _make(props, woven_cls, fabric_cls):
    """The BSDF a ``woven`` plugin's properties describe: a microcylinder fabric when
    ``material`` names one, otherwise the woven cloth."""
    if "material" in props and "table" not in props:
        try:
            opened = woven.open_material(str(props["material"]))
        except ValueError as e:
            raise ValueError(f"woven BSDF: {e}") from None
        if isinstance(opened, woven.Microcylinder):
            return fabric_cls(props, opened)
    return woven_cls(props)


def __getattr__(name):
    if name == "WovenBSDF":
        import mitsuba as mi

        return _bsdf_class(mi)
    if name == "MicrocylinderBSDF":
        import mitsuba as mi

        return _microcylinder_class(mi)
    raise AttributeError(name)
