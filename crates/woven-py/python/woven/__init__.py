"""woven: the Yang–Ikeuchi woven-cloth BRDF in Python.

NumPy in, NumPy out, computed by the Rust library ``woven``::

    import numpy as np, woven
    material = woven.Material.preset("polyester-sateen")   # or Material.load("cloth.toml")
    model = material.build(wavelength_nm=550.0)            # the exact BRDF
    wi = np.array([[0.0, 0.6, 0.8]])                       # toward the light, (N, 3)
    wo = np.array([[0.3, -0.4, np.sqrt(0.75)]])            # toward the viewer, (N, 3)
    f = model.eval(wi, wo)                                 # sr^-1, without the cosine, (N,)
    table = woven.Table.build(material)                    # fast, importance-sampled
    wo, weight, pdf = table.sample(wi, np.random.rand(1, 2))

Directions are unit vectors in the cloth's frame (z the macro normal, weft along x, warp along
y), both pointing away from the surface: ``wi`` toward the light (the paper's s), ``wo`` toward
the viewer (v). Bad parameters raise ValueError with the library's message, files OSError.
Arrays are validated alike everywhere: directions finite and unit length within
``UNIT_TOLERANCE`` (1e-6), every number finite, colours and uniforms in [0, 1] (ValueError naming
the argument, the row and its value); complex arrays raise TypeError; an empty batch gives
empty results. No array a call makes may exceed ``BATCH_BUDGET_BYTES`` (2 GiB): a larger
batch raises MemoryError before allocating. Long calls stop for Ctrl-C (KeyboardInterrupt).
``woven.Surface`` is a woven material laid on a surface (pattern cells, dyes, yarn tilt, gaps,
the footprint filter), the one ``woven render`` and the Mitsuba plugin evaluate; its keys'
defaults, ranges and meanings are ``woven.SURFACE_KEYS``.
``woven.Microcylinder("microcylinder-satin-charmeuse")`` is a microcylinder fabric (Sadeghi et
al. 2013) in colour, and ``woven.Sheen`` and ``woven.RoughPlastic`` the baselines: each a
``woven.Bsdf`` with ``eval`` (f per channel, (N, 3)), ``pdf``, ``sample`` and ``albedo``;
``woven.open_material(name)`` opens a preset or file of either model.
``woven.fit(data, model)`` fits measurements as ``woven fit --data`` does, ``woven.render(scene)``
renders a scene file as ``woven render``; ``woven.batch`` runs many fits, tables or renders on any
``concurrent.futures.Executor`` (a dask cluster: docs/batch.md).
``woven.mitsuba.register()`` adds the ``woven`` BSDF to Mitsuba 3.
"""

from ._woven import (
    BATCH_BUDGET_BYTES,
    MAX_DYED_DIFFUSE,
    JIT_LAYOUT_VERSION,
    PARALLEL_MIN,
    SURFACE_KEYS,
    UNIT_TOLERANCE,
    Bsdf,
    Material,
    Microcylinder,
    Model,
    RoughPlastic,
    Section,
    Sheen,
    Surface,
    Table,
    __version__,
    comparison_table,
    datasets,
    export_merl,
    fit,
    from_spherical,
    gonio,
    open_material,
    portable_scene,
    STANDARD_VERSION,
    standard_eval,
    standard_surface,
    presets,
    render,
    set_threads,
    threads,
    to_spherical,
    write_image,
)
from . import batch  # noqa: E402  (stdlib only; dask is imported when asked for)

__all__ = [
    "Material",
    "Model",
    "Bsdf",
    "Microcylinder",
    "Sheen",
    "RoughPlastic",
    "open_material",
    "Section",
    "Surface",
    "Table",
    "export_merl",
    "from_spherical",
    "to_spherical",
    "gonio",
    "presets",
    "fit",
    "datasets",
    "comparison_table",
    "render",
    "portable_scene",
    "STANDARD_VERSION",
    "standard_eval",
    "standard_surface",
    "write_image",
    "set_threads",
    "threads",
    "batch",
    "PARALLEL_MIN",
    "BATCH_BUDGET_BYTES",
    "UNIT_TOLERANCE",
    "MAX_DYED_DIFFUSE",
    "JIT_LAYOUT_VERSION",
    "SURFACE_KEYS",
    "__version__",
]
