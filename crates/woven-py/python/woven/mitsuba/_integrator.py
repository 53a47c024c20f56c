"""``woven_path``: Mitsuba 3's ``path`` estimator that hands the camera ray's footprint to the
first surface it meets, so that a woven BSDF's ``detail = "auto"`` and its footprint filter work
as in ``woven render``.

Mitsuba's ``path`` integrator drops a camera ray's differentials before it traces it, so a BSDF
never learns how much of the surface a pixel covers (``si.duv_dx``, ``si.duv_dy`` stay zero). This
integrator is the same estimator — emitters hit with multiple importance sampling against the
BSDF's draw, next-event estimation with MIS, Russian roulette from ``rr_depth`` on, at most
``max_depth`` vertices — written in Dr.Jit, with one difference: at the first vertex it computes
the uv partials from the camera ray's differentials (``si.compute_uv_partials``), scaled back to a
whole pixel's step as ``woven render``'s footprint is (Mitsuba scales a camera ray's
differentials by 1/√spp). Later vertices have none, as in ``woven render``.

Keys: ``max_depth`` (default 6, -1 for no limit, as ``path``'s) and ``rr_depth`` (default 5).
``hide_emitters`` is ``path``'s.
"""

from __future__ import annotations


# The most surfaces a shadow ray passes straight through (`woven render`'s bound).
MAX_PASSES = 64


def _passed(mi, dr, scene, si, ds, active):
    """The share of the light from the emitter sample ``ds`` that reaches ``si``: 0 where an
    opaque surface stands between, the product of each surface's null transmission
    (``eval_null_transmission``: what passes straight between a sheer's yarns) where only such
    surfaces do, as ``woven render``'s shadow rays and Mitsuba's ``volpath`` carry it."""
    passed = mi.Spectrum(1.0)
    ray = si.spawn_ray_to(ds.p)
    if not dr.is_jit_v(mi.Float):
        # One lane: the surfaces met in turn (a scalar variant's invalid hit has no BSDF).
        for _ in range(MAX_PASSES if active else 0):
            hit = scene.ray_intersect(ray, ray_flags=mi.RayFlags.All, coherent=False)
            if not hit.is_valid():
                return passed
            bsdf = hit.bsdf()
            if not mi.has_flag(bsdf.flags(), mi.BSDFFlags.Null):
                return mi.Spectrum(0.0)
            passed = passed * bsdf.eval_null_transmission(hit)
            if dr.max(passed) <= 0:
                return passed
            ray = hit.spawn_ray_to(ds.p)
        return mi.Spectrum(0.0)
    state = (ray, passed, mi.UInt32(0), mi.Bool(active))

    def body(ray, passed, k, active):
        hit = scene.ray_intersect(ray, ray_flags=mi.RayFlags.All, coherent=False, active=active)
        met = active & hit.is_valid()
        bsdf = hit.bsdf()
        null = met & mi.has_flag(bsdf.flags(), mi.BSDFFlags.Null)
        through = bsdf.eval_null_transmission(hit, null)
        passed = dr.select(met, dr.select(null, passed * through, 0.0), passed)
        ray = dr.select(null, hit.spawn_ray_to(ds.p), ray)
        k = k + 1
        active = null & (dr.max(passed) > 0) & (k < MAX_PASSES)
        return ray, passed, k, active

    state = dr.while_loop(state, lambda *s: s[-1], body, label="woven_path shadow")
    return dr.select(active, state[1], 0.0)


def _passes(mi, scene):
    """Whether a BSDF of ``scene`` lets light straight through (has a null component)."""
    null = int(mi.BSDFFlags.Null)
    return any(
        shape.bsdf() is not None and int(shape.bsdf().flags()) & null for shape in scene.shapes()
    )


def _integrator_class(mi):
    """The ``woven_path`` integrator class for the current variant."""
    import drjit as dr

    jit = dr.is_jit_v(mi.Float)

    def no(mask):
        """A mask's negation: Dr.Jit's ``~`` in JIT variants; in scalar ones the mask is a
        Python bool, whose ``~`` is an integer's."""
        return ~mask if jit else not mask

    def mis(a, b):
        """The power heuristic (β = 2) weight of a draw with density ``a`` against ``b``."""
        a2 = dr.square(a)
        if not jit:
            # (A scalar variant's floats are Python's: both branches are evaluated.)
            return a2 / (a2 + dr.square(b)) if a > 0 else 0.0
        return dr.detach(dr.select(a > 0, a2 / (a2 + dr.square(b)), 0.0))

    class WovenPath(mi.SamplingIntegrator):
        """Mitsuba's ``path`` estimator, with the camera ray's footprint at the first vertex
        (see the module ``woven.mitsuba._integrator``)."""

        def __init__(self, props):
            mi.SamplingIntegrator.__init__(self, props)
            max_depth = props.get("max_depth", 6)
            if max_depth < -1:
                raise ValueError(
                    f"woven_path: `max_depth` = {max_depth}: expected -1 (no limit) or >= 0"
                )
            self.max_depth = 0xFFFFFFFF if max_depth == -1 else int(max_depth)
            rr_depth = props.get("rr_depth", 5)
            if rr_depth <= 0:
                raise ValueError(f"woven_path: `rr_depth` = {rr_depth}: expected > 0")
            self.rr_depth = int(rr_depth)
            self._scene_passes = None

        def sample(self, scene, sampler, ray, medium=None, active=True):
            ctx = mi.BSDFContext()
            active = mi.Bool(active)
            # The camera ray's footprint, over a whole pixel (render() scaled it by 1/√spp).
            # (A copy: RayDifferential3f(ray) keeps the ray and drops its differentials.)
            camera = mi.RayDifferential3f(ray)
            camera.o_x, camera.o_y, camera.d_x, camera.d_y = ray.o_x, ray.o_y, ray.d_x, ray.d_y
            camera.has_differentials = ray.has_differentials
            camera.scale_differential(dr.sqrt(mi.Float(sampler.sample_count())))
            ray = camera
            si = scene.ray_intersect(
                mi.Ray3f(ray), ray_flags=mi.RayFlags.All, coherent=True, active=active
            )
            si.compute_uv_partials(ray)
            # The sampler is loop state too: its draws advance from one vertex to the next.
            state = (
                sampler,
                si,
                mi.Spectrum(0.0),  # L
                mi.Spectrum(1.0),  # beta, the path's throughput
                mi.Float(1.0),  # eta, the relative index of refraction so far
                mi.UInt32(0),  # depth
                dr.zeros(mi.SurfaceInteraction3f),  # the previous vertex
                mi.Float(1.0),  # the density that drew this vertex's direction
                mi.Bool(True),  # whether that draw was a delta (no MIS for emitters)
                active,
            )
            state = dr.while_loop(
                state,
                lambda *s: s[-1],
                lambda *s: self._vertex(scene, ctx, *s),
                labels=("sampler", "si", "L", "beta", "eta", "depth", "prev", "prev_pdf", "prev_delta", "active"),
                label="woven_path",
            )
            return state[2], mi.Bool(True), []

        def _vertex(
            self, scene, ctx, sampler, si, L, beta, eta, depth, prev, prev_pdf, prev_delta, active
        ):
            """One vertex of the path: what it sees of an emitter, its light by next-event
            estimation, and the draw of the next direction."""
            # An emitter hit (the environment where the ray left the scene), weighed against
            # the light sampling that could have drawn it.
            ds = mi.DirectionSample3f(scene, si=si, ref=prev)
            if jit:
                em_pdf = dr.select(
                    prev_delta, 0.0, scene.pdf_emitter_direction(prev, ds, active & ~prev_delta)
                )
            elif active and not prev_delta and ds.emitter is not None:
                em_pdf = scene.pdf_emitter_direction(prev, ds)
            else:
                # (A scalar variant's call dereferences the emitter even for an inactive lane.)
                em_pdf = mi.Float(0.0)
            visible = active & no((depth == 0) & self.hide_emitters)
            if jit or ds.emitter is not None:
                emitted = ds.emitter.eval(si, visible)
                L = L + dr.select(visible, beta * mis(prev_pdf, em_pdf) * emitted, 0.0)
            go_on = active & si.is_valid() & (depth + 1 < self.max_depth)
            if not jit and not go_on:
                # A scalar variant's path has ended (its one lane has no BSDF to ask).
                return sampler, si, L, beta, eta, depth, prev, prev_pdf, prev_delta, mi.Bool(False)
            bsdf = si.bsdf()

            # Next-event estimation (its shadow ray through what passes light straight on).
            smooth = mi.has_flag(bsdf.flags(), mi.BSDFFlags.Smooth)
            em_active = go_on & smooth
            passing = self._passing(scene)
            ds, em_weight = scene.sample_emitter_direction(
                si, sampler.next_2d(), not passing, em_active
            )
            em_active &= ds.pdf != 0.0
            if passing:
                em_weight = em_weight * _passed(mi, dr, scene, si, ds, em_active)
            wo = si.to_local(ds.d)
            f, bsdf_pdf = bsdf.eval_pdf(ctx, si, wo, em_active)
            em_mis = dr.select(ds.delta, 1.0, mis(ds.pdf, bsdf_pdf))
            L = L + dr.select(em_active, beta * em_mis * f * em_weight, 0.0)

            # The next direction, drawn by the BSDF.
            bs, weight = bsdf.sample(ctx, si, sampler.next_1d(), sampler.next_2d(), go_on)
            beta = beta * dr.select(go_on, weight, 0.0)
            eta = eta * dr.select(go_on, bs.eta, 1.0)
            # Straight through (a null component, light between a sheer's yarns): no vertex,
            # as in `woven render`. The path keeps its last vertex, its draw's density and its
            # depth, so an emitter met beyond is weighed against that vertex's light sampling,
            # whose shadow ray passed the same way.
            on = go_on & no(mi.has_flag(bs.sampled_type, mi.BSDFFlags.Null))
            prev = dr.select(on, si, prev)
            prev_pdf = dr.select(on, bs.pdf, prev_pdf)
            prev_delta = dr.select(on, mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta), prev_delta)
            ray = si.spawn_ray(si.to_world(bs.wo))
            depth = dr.select(on, depth + 1, depth)

            # Russian roulette, as Mitsuba's `path`: on the throughput with η² folded in.
            rr_prob = dr.minimum(dr.max(beta) * dr.square(eta), 0.95)
            roulette = depth >= self.rr_depth
            beta = dr.select(roulette, beta * dr.rcp(rr_prob), beta)
            survives = no(roulette) | (sampler.next_1d() < rr_prob)
            active = go_on & survives & (dr.max(beta) != 0.0)
            si = scene.ray_intersect(ray, ray_flags=mi.RayFlags.All, coherent=False, active=active)
            return sampler, si, L, beta, eta, depth, prev, prev_pdf, prev_delta, active

        def render(self, scene, sensor, seed=0, spp=0, develop=True, evaluate=True):
            # Whether the scene passes light straight on, found once for the whole render.
            self._scene_passes = _passes(mi, scene)
            try:
                return mi.SamplingIntegrator.render(
                    self, scene, sensor, seed, spp, develop, evaluate
                )
            finally:
                self._scene_passes = None

        def _passing(self, scene):
            """Whether a BSDF of ``scene`` passes light straight on (a null component): then
            shadow rays are traced through such surfaces; else Mitsuba's own test, as ``path``'s."""
            if self._scene_passes is not None:
                return self._scene_passes
            return _passes(mi, scene)

        def aov_names(self):
            return []

        def to_string(self):
            return f"WovenPath[max_depth={self.max_depth}, rr_depth={self.rr_depth}]"

    return WovenPath
