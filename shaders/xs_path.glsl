// SPDX-License-Identifier: MIT
/**
 * @file xs_path.glsl
 * @brief The path tracer's path loop (factored out of spp.rgen, unchanged in behaviour):
 *        next-event estimation of the sun (a delta light, or the sky's disk sun with MIS), the
 *        environment map (importance-sampled with MIS, xs_env.glsl), one emissive triangle
 *        with MIS and one punctual light of XS_BIND_LIGHTS, BSDF sampling, Russian roulette
 *        (seed 000 §5.1). Used by spp.rgen (camera paths, also method `taa`'s) and by the
 *        shading passes that continue paths from a first hit (sc_shade.rgen of the sample
 *        cache and isrt, hc_shade.rgen and hc_hybrid_shade.rgen of the hash cache). Without a
 *        map, a disk sun or punctual lights no random number is drawn for them, so the paths
 *        of a constant environment are those of before.
 *
 * Light selection at each non-delta vertex: every light type gets its own estimator, summed
 * (the sun; one environment sample; one emissive triangle picked by power; one punctual light
 * picked by its power estimate, gpu_scene.h). Area, environment and disk-sun samples are
 * combined with BSDF sampling by the power heuristic; the delta sun and the punctual lights
 * are delta lights that BSDF sampling never finds, so their weight is 1 and no other MIS
 * weight changes.
 *
 * Light samples queue their shadow query (xs_shadow_push); after the estimators the loop asks
 * XS_LIGHT_VISIBLE for each, from one call site: sc_shade.rgen (XS_PATH_VISCACHE)
 * routes it to the visibility cache of seed 002 (xs_viscache.glsl), everyone else traces.
 *
 * Declares the two ray payloads at locations XS_PAYLOAD_PRIMARY / XS_PAYLOAD_SHADOW. Requires
 * xs_bindings.glsl, xs_bsdf.glsl, xs_hitinfo.glsl and xs_rng.glsl.
 */
#ifndef XS_PATH_GLSL
#define XS_PATH_GLSL

#include "xs_env.glsl"
#include "xs_viscache.h"

layout(location = XS_PAYLOAD_PRIMARY) rayPayloadEXT xs_hit payload;
layout(location = XS_PAYLOAD_SHADOW) rayPayloadEXT uint shadow_visible;

#define XS_RAY_TMAX 1e30
/* Survival probability bounds of Russian roulette. */
#define XS_RR_MIN_SURVIVAL 0.05
/* Whether the pipeline may meet smooth thin glass (gpu_rt_program_desc.glass): false compiles
 * shadow rays without their glass walk. True when a raygen is built without the constant. */
layout(constant_id = XS_SPEC_GLASS_ID) const bool XS_SPEC_GLASS = true;
#define XS_RR_MAX_SURVIVAL 1.0

/** The BSDF's view of a material (xs_bsdf.glsl). */
xs_bsdf_in xs_bsdf_input(xs_mat m)
{
    xs_bsdf_in b;
    b.base = m.base;
    b.metallic = m.metallic;
    b.roughness = m.roughness;
    b.transmission = m.transmission;
    b.ior = m.ior;
    b.spec_color = m.spec_color;
    b.specular = m.specular;
    b.clearcoat = m.clearcoat;
    b.clearcoat_roughness = m.clearcoat_roughness;
    b.sheen_color = m.sheen_color;
    b.sheen_roughness = m.sheen_roughness;
    b.thin = m.thin;
    return b;
}

/**
 * Transmittance of the smooth thin glass on a segment already free of everything else: walks
 * the XS_CULL_GLASS surfaces (closest-hit rays of that mask only) and multiplies what each
 * lets through (xs_glass_pass). More than XS_GLASS_MAX_LAYERS surfaces count as opaque. Uses
 * the primary payload: callers hold no hit in it (xs_path_trace has copied what it needs).
 */
vec3 xs_glass_transmittance(vec3 o, vec3 d, float tmax, inout uint rays)
{
    vec3 tr = vec3(1.0);
    for (uint k = 0u; k <= XS_GLASS_MAX_LAYERS; k++) {
        payload.instance = XS_MISS_INSTANCE;
        traceRayEXT(xs_tlas, XS_RAY_FLAGS_BOUNCE, XS_CULL_GLASS, 0, 0, XS_MISS_INDEX_PRIMARY, o,
                    0.0, d, tmax, XS_PAYLOAD_PRIMARY);
        rays++;
        if (payload.instance == XS_MISS_INSTANCE)
            return tr;
        if (k == XS_GLASS_MAX_LAYERS)
            break;
        float t = payload.t;
        xs_surface s =
            xs_surface_at(payload.instance, payload.primitive, vec2(payload.bary_u, payload.bary_v));
        xs_surface_orient(s, -d);
        xs_mat m = xs_material_at(s.material, s.uv);
        tr *= xs_glass_pass(xs_bsdf_input(m), dot(-d, s.ns));
        if (!(xs_max3(tr) > 0.0))
            break;
        o = xs_offset_ray(s.p, -s.ng); /* s.ng faces -d: continue behind the surface */
        tmax -= t;
    }
    return vec3(0.0);
}

/**
 * Visibility of a light sample: the segment from (offset) origin o along unit d up to tmax.
 * Shadow rules (issue 18): opaque, MASK and BLEND surfaces block as their any-hit shader says
 * (hit.rahit); smooth thin-walled glass (XS_MAT_GLASS_SHADOW) lets the light through, tinted
 * (xs_glass_transmittance): exact, since its delta transmission goes straight on.
 * xs_path_trace treats a path's delta transmission through the same glass as a null event for
 * MIS, so the light is counted once. A refracting volume (KHR_materials_volume) and rough
 * glass block, as physics says for a straight line: the light they pass comes by BSDF
 * sampling (caustics) and by rough glass's own light sampling. Without such glass in the
 * scene this is the one shadow ray of before.
 */
vec3 xs_visible(vec3 o, vec3 d, float tmax, inout uint rays)
{
    bool glass = XS_SPEC_GLASS && frame.glass_instances > 0u;
    shadow_visible = 0u;
    traceRayEXT(xs_tlas, XS_RAY_FLAGS_SHADOW, glass ? XS_CULL_NO_GLASS : XS_CULL_ALL, 0, 0,
                XS_MISS_INDEX_SHADOW, o, 0.0, d, tmax, XS_PAYLOAD_SHADOW);
    rays++;
    if (shadow_visible == 0u)
        return vec3(0.0);
    return glass ? xs_glass_transmittance(o, d, tmax, rays) : vec3(1.0);
}

/** glTF alpha coverage at point bary of a triangle: MASK 0 in a hole and 1 elsewhere, BLEND
 *  alpha (the probability that a ray stops there, hit.rahit), OPAQUE 1. Scales a light
 *  sample's emission, so that holes emit nothing, as rays through them find nothing. */
float xs_coverage(uint instance, uint primitive, vec2 bary)
{
    xs_material m = materials[instances[instance].material];
    if ((m.flags & (XS_MAT_ALPHA_MASK | XS_MAT_ALPHA_BLEND)) == 0u)
        return 1.0;
    float a = xs_alpha_at(m, instance, primitive, bary);
    if ((m.flags & XS_MAT_ALPHA_MASK) != 0u)
        return a >= m.alpha_cutoff ? 1.0 : 0.0;
    return clamp(a, 0.0, 1.0);
}

/* The shadow query of a light sample. With XS_PATH_VISCACHE (sc_shade.rgen) it goes to the
 * visibility cache (xs_viscache.glsl: X = s, the side `below`, the light end kind / lp / ln /
 * density, seed 002 §3.5), which answers at the first vertex; otherwise (spp.rgen) it is a
 * plain xs_visible and the extra arguments are never evaluated. */
#ifdef XS_PATH_VISCACHE
vec3 xs_vc_visible(vec3 o, vec3 d, float tmax, uint bounce, xs_surface s, bool below,
                   uint kind, vec3 lp, vec3 ln, float density, inout uint rays);
#define XS_LIGHT_VISIBLE(o, d, tmax, bounce, s, below, kind, lp, ln, density, rays)            \
    xs_vc_visible(o, d, tmax, bounce, s, below, kind, lp, ln, density, rays)
/* a visibility cache pre-pass launch: the path stops after the first vertex's light samples */
bool xs_vc_prepass();
#define XS_PATH_STOP_AFTER_LIGHTS(bounce) ((bounce) == 0u && xs_vc_prepass())
#else
#define XS_PATH_STOP_AFTER_LIGHTS(bounce) false
#define XS_LIGHT_VISIBLE(o, d, tmax, bounce, s, below, kind, lp, ln, density, rays)            \
    xs_visible(o, d, tmax, rays)
#endif

/* The light samples of one vertex (at most one per estimator) wait here for their shadow
 * queries, which the path loop makes from one call site: the driver inlines every call site
 * of xs_visible with its walk through glass; with six of them a cold compile of spp.rgen's
 * pipeline on lavapipe ran past 10 minutes on the loaded build machine. */
#define XS_MAX_SHADOW_QUERIES 5u
struct xs_shadow_query {
    vec3 c; /* the contribution if visible */
    vec3 o, d;
    float tmax;
    bool below;
    uint kind;
    vec3 lp, ln;
    float density;
};
xs_shadow_query xs_sq[XS_MAX_SHADOW_QUERIES];
uint xs_sq_count;

/** Queues the shadow query of a light sample (XS_LIGHT_VISIBLE's arguments, contribution c). */
void xs_shadow_push(vec3 c, vec3 o, vec3 d, float tmax, bool below, uint kind, vec3 lp, vec3 ln,
                    float density)
{
    if (xs_sq_count >= XS_MAX_SHADOW_QUERIES)
        return;
    xs_shadow_query q;
    q.c = c;
    q.o = o;
    q.d = d;
    q.tmax = tmax;
    q.below = below;
    q.kind = kind;
    q.lp = lp;
    q.ln = ln;
    q.density = density;
    xs_sq[xs_sq_count] = q;
    xs_sq_count++;
}

/** Index of the emitter whose cdf interval holds u (first i with cdf[i] > u). */
uint xs_pick_emitter(float u)
{
    uint lo = 0u;
    uint hi = frame.emitter_count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (emitters[mid].cdf > u)
            hi = mid;
        else
            lo = mid + 1u;
    }
    return lo;
}

/** Index of the punctual light whose cdf interval holds u (first i with cdf[i] > u). */
uint xs_pick_light(float u)
{
    uint lo = 0u;
    uint hi = frame.light_count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi) >> 1u;
        if (lights[mid].cdf > u)
            hi = mid;
        else
            lo = mid + 1u;
    }
    return lo;
}

/** glTF KHR_lights_punctual's recommended range window: clamp(1 - (d / range)^4, 0, 1), 1 for
 *  range 0 (infinite). */
float xs_range_window(float d, float range)
{
    if (!(range > 0.0))
        return 1.0;
    float x = d / range;
    x *= x;
    return clamp(1.0 - x * x, 0.0, 1.0);
}

/** glTF's spot attenuation (the spec's implementation note): a squared linear ramp in the
 *  cosine between the axis and the direction from the light, 1 inside the inner cone. */
float xs_spot_attenuation(xs_light l, vec3 from_light)
{
    float a = clamp(dot(l.direction.xyz, from_light) * l.spot_scale + l.spot_offset, 0.0, 1.0);
    return a * a;
}

/** Light-sampling pdf (solid angle at the receiver) of a point on an emissive triangle. */
float xs_light_pdf(float pmf, float area, float dist2, float cos_light)
{
    return area > 0.0 && cos_light > 0.0 ? pmf * dist2 / (area * cos_light) : 0.0;
}

/** True when wi leaves on the geometric side that its local z says (reflection above, trans-
 *  mission below): keeps light leaks through smooth-shaded meshes out of both estimators. */
bool xs_side_ok(vec3 wi_world, vec3 ng, float wi_local_z)
{
    return dot(wi_world, ng) * wi_local_z > 0.0;
}

struct xs_path_out {
    vec3 radiance;
    vec3 albedo; /* xs_demod_albedo of the first hit (1 for a miss) */
    xs_hit first;
    float depth; /* set by callers that know the camera (xs_trace_path) */
    uint rays;
};

/** Next-event estimation towards infinity: light sample wi (unit, world) with solid-angle pdf
 *  pl and radiance le, power-heuristic MIS against the BSDF's pdf of wi. */
void xs_add_light_sample(inout xs_path_out r, vec3 throughput, vec3 wi, float pl, vec3 le,
                         xs_bsdf bsdf, vec3 wo_l, vec3 tb, vec3 bb, xs_surface s, vec3 o_up,
                         uint bounce)
{
    if (!(pl > 0.0) || !any(greaterThan(le, vec3(0.0))))
        return;
    vec3 wi_l = xs_to_local(wi, tb, bb, s.ns);
    float pdf_b;
    vec3 fc = xs_bsdf_eval(bsdf, wo_l, wi_l, pdf_b);
    if (!any(greaterThan(fc, vec3(0.0))) || !xs_side_ok(wi, s.ng, wi_l.z))
        return;
    vec3 c = throughput * fc * le * (xs_mis_power(pl, pdf_b) / pl);
    if (!xs_finite(c))
        return;
    vec3 o = wi_l.z > 0.0 ? o_up : xs_offset_ray(s.p, -s.ng);
    xs_shadow_push(c, o, wi, XS_RAY_TMAX, wi_l.z <= 0.0, XS_VC_LIGHT_SOLID_ANGLE, wi, vec3(0.0),
                   pl);
}

/** Next-event estimation of one punctual light picked by u (a delta light: weight 1, divided
 *  by its pick probability). Point and spot: irradiance I / d^2 x spot x range window at the
 *  receiver; directional: its irradiance. */
void xs_add_punctual_light(inout xs_path_out r, vec3 throughput, float u, xs_bsdf bsdf,
                           vec3 wo_l, vec3 tb, vec3 bb, xs_surface s, vec3 o_up, uint bounce)
{
    xs_light l = lights[xs_pick_light(u)];
    float pmf = l.intensity.w;
    vec3 wi = l.direction.xyz;
    vec3 e = l.intensity.rgb;
    if (l.type != XS_LIGHT_DIRECTIONAL) {
        vec3 to_l = l.position.xyz - s.p;
        float d2 = dot(to_l, to_l);
        if (!(d2 > 0.0))
            return;
        float d = sqrt(d2);
        wi = to_l / d;
        float att = xs_range_window(d, l.position.w) / d2;
        if (l.type == XS_LIGHT_SPOT)
            att *= xs_spot_attenuation(l, -wi);
        e *= att;
    }
    if (!(pmf > 0.0) || !any(greaterThan(e, vec3(0.0))))
        return;
    vec3 wi_l = xs_to_local(wi, tb, bb, s.ns);
    float pdf_b;
    vec3 fc = xs_bsdf_eval(bsdf, wo_l, wi_l, pdf_b);
    if (!any(greaterThan(fc, vec3(0.0))) || !xs_side_ok(wi, s.ng, wi_l.z))
        return;
    vec3 c = throughput * fc * e / pmf;
    if (!xs_finite(c))
        return;
    vec3 o = wi_l.z > 0.0 ? o_up : xs_offset_ray(s.p, -s.ng);
    bool below = wi_l.z <= 0.0;
    if (l.type == XS_LIGHT_DIRECTIONAL) {
        xs_shadow_push(c, o, wi, XS_RAY_TMAX, below, XS_VC_LIGHT_DIRECTION, wi, vec3(0.0), 1.0);
        return;
    }
    vec3 seg = l.position.xyz - o; /* the shadow ray ends at the light */
    float len = length(seg);
    if (len > 0.0)
        xs_shadow_push(c, o, seg / len, len, below, XS_VC_LIGHT_POINT, l.position.xyz,
                       vec3(0.0), 1.0);
}

/**
 * One path from origin along unit dir. With have_first, the first vertex is `first` (a hit
 * already known, e.g. a cached first hit of the sample cache: no ray is traced for it);
 * first.t then only matters for MIS of its emission, which first_emission = false drops
 * (the sample cache adds the first hit's emission at reconstruction, seed 000 §3.3).
 */
xs_path_out xs_path_trace(vec3 origin, vec3 dir, bool have_first, xs_hit first,
                          bool first_emission, inout xs_rng rng)
{
    xs_path_out r;
    r.radiance = vec3(0.0);
    r.albedo = vec3(1.0);
    r.first.instance = XS_MISS_INSTANCE;
    r.depth = 0.0;
    r.rays = 0u;

    vec3 throughput = vec3(1.0);
    float prev_pdf = 0.0;  /* BSDF pdf of the ray just traced (solid angle) */
    bool prev_delta = true; /* camera rays and delta lobes: emission counts fully */
    float glass_t = 0.0;    /* distance through glass passed as shadow rays pass it (below) */
    uint max_bounces = frame.max_bounces;
    /* Straight passes through smooth thin glass (the null events below) do not count as
     * bounces, up to XS_GLASS_MAX_LAYERS per path, as shadow rays pass that many: they scatter
     * nothing aside, like Cycles' transparent bounces, which have their own limit. Counted,
     * a path through a thin sphere spent two of the default three bounces on its walls, and
     * TransmissionTest's glass came out 12 % darker than with 8 bounces (bench/results/cycles). */
    uint glass_passes = 0u;

    for (uint bounce = 0u;; bounce++) {
        if (bounce == 0u && have_first) {
            payload = first;
        } else {
            payload.instance = XS_MISS_INSTANCE;
            /* bounce 0 here is a camera ray (spp.rgen) */
            traceRayEXT(xs_tlas, bounce == 0u ? XS_RAY_FLAGS_CAMERA : XS_RAY_FLAGS_BOUNCE,
                        XS_CULL_ALL, 0, 0, XS_MISS_INDEX_PRIMARY, origin, 0.0, dir, XS_RAY_TMAX,
                        XS_PAYLOAD_PRIMARY);
            r.rays++;
        }
        if (bounce == 0u)
            r.first = payload;
        if (payload.instance == XS_MISS_INSTANCE) {
            r.radiance += throughput * xs_env_escape(dir, prev_delta, prev_pdf);
            break;
        }

        uint instance = payload.instance;
        uint primitive = payload.primitive;
        float t_hit = payload.t;
        vec3 wo = -dir;
        xs_surface s = xs_surface_at(instance, primitive, vec2(payload.bary_u, payload.bary_v));
        xs_surface_orient(s, wo);
        xs_mat m = xs_material_at(s.material, s.uv);
        if (bounce == 0u)
            r.albedo = xs_demod_albedo(m);
        /* KHR_materials_volume: Beer-Lambert absorption along the segment inside the volume
         * this ray leaves (its own surface bounds it; nested volumes are not tracked) */
        if (!s.outside && !m.thin && m.transmission > 0.0 && any(greaterThan(m.sigma_a, vec3(0.0))))
            throughput *= exp(-m.sigma_a * t_hit);

        /* emission reached by this ray */
        vec3 le = bounce > 0u || first_emission ? xs_emitted(m, s.outside) : vec3(0.0);
        if (any(greaterThan(le, vec3(0.0)))) {
            float w = 1.0;
            uint ebase = instances[instance].emitter_base;
            if (!prev_delta && ebase != XS_NO_EMITTER && frame.emitter_count > 0u) {
                float pmf = emitters[ebase + primitive].pmf;
                float dl = glass_t + t_hit;
                float pl = xs_light_pdf(pmf, s.area, dl * dl, abs(dot(wo, s.ng)));
                w = xs_mis_power(prev_pdf, pl);
            }
            r.radiance += throughput * le * w;
        }
        if (bounce >= max_bounces + glass_passes)
            break;

        vec3 tb, bb;
        xs_onb(s.ns, tb, bb);
        vec3 wo_l = xs_to_local(wo, tb, bb, s.ns);
        xs_bsdf bsdf = xs_bsdf_make(xs_bsdf_input(m), wo_l.z, s.outside, xs_rng_next(rng));
        bool delta = xs_bsdf_is_delta(bsdf);
        vec3 o_up = xs_offset_ray(s.p, s.ng);

        xs_sq_count = 0u;
        if (!delta) {
            /* the sky's sun disk and the environment map: light samples with MIS */
            if (frame.sun_direction.w > 0.0 && frame.sun_cos_max > 0.0) {
                float pl = 1.0 / xs_sun_solid_angle();
                xs_add_light_sample(r, throughput, xs_sun_sample(xs_rng_next2(rng)), pl,
                                    frame.sun_radiance.rgb * pl, bsdf, wo_l, tb, bb, s, o_up,
                                    bounce);
            }
            if (frame.env_width > 0u && frame.env_sampling != 0u) {
                vec3 wi;
                float pl;
                vec3 le = xs_env_sample(xs_rng_next2(rng), wi, pl);
                xs_add_light_sample(r, throughput, wi, pl, le, bsdf, wo_l, tb, bb, s, o_up,
                                    bounce);
            }
            /* the sun: a delta light, no MIS */
            if (frame.sun_direction.w > 0.0 && frame.sun_cos_max <= 0.0) {
                vec3 wi = frame.sun_direction.xyz;
                vec3 wi_l = xs_to_local(wi, tb, bb, s.ns);
                float pdf_b;
                vec3 fc = xs_bsdf_eval(bsdf, wo_l, wi_l, pdf_b);
                if (any(greaterThan(fc, vec3(0.0))) && xs_side_ok(wi, s.ng, wi_l.z)) {
                    vec3 o = wi_l.z > 0.0 ? o_up : xs_offset_ray(s.p, -s.ng);
                    xs_shadow_push(throughput * fc * frame.sun_radiance.rgb, o, wi, XS_RAY_TMAX,
                                   wi_l.z <= 0.0, XS_VC_LIGHT_DIRECTION, wi, vec3(0.0), 1.0);
                }
            }
            /* one emissive triangle */
            if (frame.emitter_count > 0u) {
                float ue = xs_rng_next(rng);
                vec2 ut = xs_rng_next2(rng);
                xs_emitter e = emitters[xs_pick_emitter(ue)];
                vec2 lbary = xs_sample_triangle(ut);
                xs_surface ls = xs_surface_at(e.instance, e.primitive, lbary);
                vec3 to_l = ls.p - s.p;
                float dist2 = dot(to_l, to_l);
                if (dist2 > 0.0 && e.pmf > 0.0) {
                    vec3 wi = to_l * inversesqrt(dist2);
                    xs_surface_orient(ls, -wi);
                    xs_mat lm = xs_material_at(ls.material, ls.uv);
                    vec3 lle = xs_emitted(lm, ls.outside) *
                               xs_coverage(e.instance, e.primitive, lbary);
                    float pl = xs_light_pdf(e.pmf, ls.area, dist2, dot(-wi, ls.ng));
                    vec3 wi_l = xs_to_local(wi, tb, bb, s.ns);
                    float pdf_b;
                    vec3 fc = xs_bsdf_eval(bsdf, wo_l, wi_l, pdf_b);
                    if (pl > 0.0 && any(greaterThan(fc * lle, vec3(0.0))) &&
                        xs_side_ok(wi, s.ng, wi_l.z)) {
                        vec3 o = wi_l.z > 0.0 ? o_up : xs_offset_ray(s.p, -s.ng);
                        vec3 target = xs_offset_ray(ls.p, ls.ng);
                        vec3 seg = target - o;
                        float len = length(seg);
                        if (len > 0.0) {
                            float w = xs_mis_power(pl, pdf_b);
                            vec3 c = throughput * fc * lle * (w / pl);
                            if (xs_finite(c))
                                xs_shadow_push(c, o, seg / len, len, wi_l.z <= 0.0,
                                               XS_VC_LIGHT_AREA, ls.p, ls.ng, e.pmf / ls.area);
                        }
                    }
                }
            }
            /* one punctual light (after the others: their random numbers stay where they were) */
            if (frame.light_count > 0u)
                xs_add_punctual_light(r, throughput, xs_rng_next(rng), bsdf, wo_l, tb, bb, s,
                                      o_up, bounce);
        }
        /* the shadow queries, in the order the estimators made them */
        for (uint i = 0u; i < xs_sq_count; i++) {
            xs_shadow_query q = xs_sq[i];
            r.radiance += q.c * XS_LIGHT_VISIBLE(q.o, q.d, q.tmax, bounce, s, q.below, q.kind,
                                                 q.lp, q.ln, q.density, r.rays);
        }

        if (XS_PATH_STOP_AFTER_LIGHTS(bounce))
            break;
        /* BSDF sampling of the bounce ray */
        vec3 u3 = vec3(xs_rng_next2(rng), xs_rng_next(rng));
        vec3 wi_l, weight;
        float pdf;
        bool is_delta;
        if (!xs_bsdf_sample(bsdf, wo_l, u3, wi_l, weight, pdf, is_delta))
            break;
        vec3 wi = normalize(xs_to_world(wi_l, tb, bb, s.ns));
        if (!xs_side_ok(wi, s.ng, wi_l.z))
            break;
        throughput *= weight;
        /* a delta transmission through glass that shadow rays pass (xs_visible): a null event
         * for MIS and for the bounce count (below) */
        bool glass_pass = is_delta && wi_l.z < 0.0 && XS_SPEC_GLASS && frame.glass_instances > 0u &&
                          (materials[s.material].flags & XS_MAT_GLASS_SHADOW) != 0u;

        /* Russian roulette before bounce ray number bounce + 1, counting bounces as the limit
         * does (glass passes not), and not at a pass: a path through a tinted thin sphere was
         * ended at its back wall with probability 1 - max(tint^2) (28 % for TransmissionTest's
         * blue), binary noise on every glass pixel. Survival follows the throughput
         * alone: pbrt's etaScale (undoing refraction's radiance scaling, so that paths inside
         * glass survive more often) was tried and taken out, because the extra caustic paths
         * through the Cornell box's glass sphere made the sample cache's relMSE rise between
         * frames 8 and 16 (test_samplecache_shading's convergence check). */
        if (!glass_pass && bounce + 1u - glass_passes >= XS_RR_START_BOUNCE) {
            float q = clamp(xs_max3(throughput), XS_RR_MIN_SURVIVAL,
                            XS_RR_MAX_SURVIVAL);
            if (xs_rng_next(rng) >= q)
                break;
            throughput /= q;
        }
        if (!xs_finite(throughput) || xs_max3(throughput) <= 0.0)
            break;

        origin = wi_l.z > 0.0 ? o_up : xs_offset_ray(s.p, -s.ng);
        dir = wi;
        /* A delta transmission through glass that shadow rays pass (xs_visible) is a null
         * event for MIS: the emission found behind it is weighted against the light sample
         * of the last scattering vertex, whose shadow ray came through the same glass, with
         * the distance summed over the straight segments. */
        if (glass_pass) {
            glass_t += t_hit;
            glass_passes = min(glass_passes + 1u, XS_GLASS_MAX_LAYERS);
        } else {
            prev_pdf = pdf;
            prev_delta = is_delta;
            glass_t = 0.0;
        }
    }
    if (!xs_finite(r.radiance))
        r.radiance = vec3(0.0);
    return r;
}

#endif
