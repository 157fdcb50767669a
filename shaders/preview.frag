#version 330 core
// The tracer's local shading (spec §7.1-7.3, §13.9) without reflection or refraction:
//   C = t_E * K_E + t * K_A * A_global
//     + sum over lights of  t * K_A * A_l * f_l                     (never shadowed, any N.L)
//     + sum over lights with N.L > 0 of  S * f_l * (t * K_D * D_l * N.L + t_S * K_S * S'_l * spec)
// with spec = (R_v.L)^e when R_v.L > 0, the two-sided normal facing the eye, t the texel and
// t_E = t_S = t when the scene textures every term (V3, u_texture_all), else 1. A V0/V1 light has
// A_l = 0 and D_l = S'_l (its one colour); a V3 scene has no global ambient (A_global = 0).
// f_l: 1 for directional lights; point, spot and sphere lights (at the centre) attenuate by
// 1 / (ca + la d + qa d^2); spots cut off by angle and fall off as cos^p (factor 1 when p = 0);
// a non-positive denominator gives no light (the ambient included).
// S is 1, or with shadows on the visibility looked up in the light's shadow map (opaque
// occluders), times the product of the T of the transparent surfaces on the light's way
// (RT_TRANSMIT_SHADOWS: the transmittance map; the trace also averages a sphere light's
// visibility over its sphere).
//
// The program is compiled for what a scene uses (Preview::program_for inserts the defines after
// the #version line): RT_POINT, RT_SPOT, RT_DIRECTIONAL (light kinds present; sphere lights
// count as point lights), RT_TEXTURES (some material is textured), RT_SPECULAR (some material
// has a highlight), RT_SHADOWS, RT_CSG (a set has CSG nodes: fragments of a leaf surface that
// the spec §13.8 rules reject are discarded, so the depth test keeps the nearest valid one),
// RT_REFLECTIONS (depth >= 2 and a material reflects or transmits: spec §7.4's
//   + K_S * (reflected)  + T * (refracted)
// with both looked up in an environment cube map rendered from the object's centre, one bounce
// deep, whose alpha holds the distance of what each texel sees, so the lookup is corrected for
// the parallax between the map's centre and the fragment), RT_ENV_PASS (that map's own pass:
// alpha = distance from u_pass_centre), RT_PLANAR (fragments on the planes of planar
// reflections read them instead of the cube map: planar.cpp), RT_CLIP_PLANE (a planar
// reflection's own pass), RT_INNER_HITS (still frames: what a glass solid mirrors inside is
// followed for up to four hits, not one).
const int kMaxLights = 16;

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

uniform vec3 u_eye;
uniform bool u_mirrored;  // the instance's transform mirrors: the winding seen is reversed
uniform vec3 u_ambient_light;
uniform vec3 u_emissive;
uniform vec3 u_ambient;
uniform vec3 u_diffuse;
uniform vec3 u_specular;
uniform float u_exponent;
#ifdef RT_TEXTURES
uniform bool u_textured;
uniform bool u_texture_all;
uniform sampler2D u_texture;
#endif

uniform int u_light_count;
uniform int u_light_kind[kMaxLights];  // 0 directional, 1 point, 2 spot
uniform vec3 u_light_ambient[kMaxLights];   // A_l
uniform vec3 u_light_diffuse[kMaxLights];   // D_l
uniform vec3 u_light_specular[kMaxLights];  // S'_l
uniform vec3 u_light_position[kMaxLights];
uniform vec3 u_light_direction[kMaxLights];  // unit: travel (directional) or axis (spot)
uniform vec3 u_light_atten[kMaxLights];      // ca, la, qa
uniform float u_light_cutoff[kMaxLights];
uniform float u_light_exponent[kMaxLights];

#ifdef RT_SHADOWS
// Shadow maps: six depth layers reserved per light; a directional light uses the first (an
// orthographic view along its direction over the scene's bounds), a point or spot light all six
// (cube faces, depth = distance / far).
// The layout and the face frames are Preview::render_shadow_maps' (preview.cpp).
uniform sampler2DArrayShadow u_shadow_map;
uniform float u_shadow_res;
uniform int u_shadow_layer[kMaxLights];  // first layer, -1: not shadowed in the preview
uniform vec3 u_shadow_centre[kMaxLights];
uniform vec3 u_shadow_a1[kMaxLights];
uniform vec3 u_shadow_a2[kMaxLights];
uniform float u_shadow_scale[kMaxLights];  // half extent (directional) or far distance
const vec3 kFaceForward[6] = vec3[6](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0),
                                     vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 kFaceRight[6] = vec3[6](vec3(0, 0, -1), vec3(0, 0, 1), vec3(1, 0, 0),
                                   vec3(1, 0, 0), vec3(1, 0, 0), vec3(-1, 0, 0));
const vec3 kFaceUp[6] = vec3[6](vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 0, -1),
                                vec3(0, 0, 1), vec3(0, 1, 0), vec3(0, 1, 0));

#ifdef RT_TRANSMIT_SHADOWS
// Light through transparent surfaces (spec §7.1's S_l, a product of their T): the map of the
// layer holds the product of every transparent surface's T along the light's view (rgb) and
// the depth of the nearest (alpha); a point beyond that depth gets the product.
uniform sampler2DArray u_transmit_map;
vec3 transmitted(vec2 s, float layer, float depth) {
    vec4 m = texture(u_transmit_map, vec3(s, layer));
    return depth > m.a + 2.0 / 255.0 ? m.rgb : vec3(1.0);
}
#else
vec3 transmitted(vec2 s, float layer, float depth) { return vec3(1.0); }
#endif

// Visibility of light i from p (normal n facing the light's side): the point is first moved
// along n by one and a half shadow-map texels (normal-offset shadows), then compared with a
// 2x2 filtered lookup; times the light transparent surfaces let through.
vec3 visibility(int i, vec3 p, vec3 n) {
    int layer = u_shadow_layer[i];
    if (layer < 0) return vec3(1.0);
    if (u_light_kind[i] == 0) {
        float texel = 2.0 * u_shadow_scale[i] / u_shadow_res;
        vec3 q = (p + 1.5 * texel * n - u_shadow_centre[i]) / u_shadow_scale[i];
        vec3 s = 0.5 + 0.5 * vec3(dot(q, u_shadow_a1[i]), dot(q, u_shadow_a2[i]),
                                  dot(q, u_light_direction[i]));
        return texture(u_shadow_map, vec4(s.xy, float(layer), s.z - 0.5 / u_shadow_res)) *
               transmitted(s.xy, float(layer), s.z);
    }
    vec3 v = p - u_light_position[i];
    vec3 a = abs(v);
    int f = (a.x >= a.y && a.x >= a.z) ? (v.x > 0.0 ? 0 : 1)
            : (a.y >= a.z)             ? (v.y > 0.0 ? 2 : 3)
                                       : (v.z > 0.0 ? 4 : 5);
    float texel = 2.0 * dot(v, kFaceForward[f]) / u_shadow_res;
    v += 1.5 * texel * n;
    float w = dot(v, kFaceForward[f]);
    if (w <= 0.0) return vec3(1.0);
    vec2 s = 0.5 + 0.5 * vec2(dot(v, kFaceRight[f]), dot(v, kFaceUp[f])) / w;
    float ref = length(v) / u_shadow_scale[i] - 0.5 / u_shadow_res;
    return texture(u_shadow_map, vec4(s, float(layer + f), ref)) *
           transmitted(s, float(layer + f), length(v) / u_shadow_scale[i]);
}
#endif


#ifdef RT_CSG
flat in int v_leaf;  // the CSG leaf of the fragment, -1: none
in vec3 v_set;
bool csg_valid(int l, vec3 p);  // csg.frag
#endif

out vec4 frag_color;

#ifdef RT_ENV_PASS
uniform vec3 u_pass_centre;  // the centre of the map this pass renders
#endif
#ifdef RT_REFLECTIONS
uniform vec3 u_env_centre;  // the centre of the map of this material's object
uniform bool u_env_on;  // this material reflects or transmits, and has a map
uniform vec3 u_background;  // what a ray that meets nothing sees (linear)
uniform samplerCube u_env;
uniform vec3 u_transparent;  // T
uniform float u_refind;
// The solid a transmitting range is in its set's frame (preview.cpp's set_solid_uniforms: 0 none,
// 1 a sphere, u_solid_sphere's centre and radius, 2 a box, u_solid_lo to u_solid_hi, 3 a torus
// about y, centred at u_solid_sphere.xyz, ring and tube radii u_solid_radii), and the
// instance's transforms (preview.vert's, and their inverse).
uniform int u_solid;
uniform vec4 u_solid_sphere;
uniform vec2 u_solid_radii;
uniform vec3 u_solid_lo, u_solid_hi;
uniform mat4 u_world_from_object;
uniform mat4 u_set_from_world;
uniform mat3 u_normal_matrix;
uniform int u_inner_hits;  // hits inside a solid the depth limit lets the trace shade
// Of those, followed: four in still frames (RT_INNER_HITS), else the first only.
#ifdef RT_INNER_HITS
const int kInnerTraced = 4;
#else
const int kInnerTraced = 1;
#endif

// A torus about y (spec §13.7's surface) of ring and tube radii R and r, at q from its centre:
// the distance to it (negative inside) and the outward normal's direction.
float torus_distance(vec3 q, float R, float r) { return length(vec2(length(q.xz) - R, q.y)) - r; }
vec3 torus_normal(vec3 q, float R) {
    float k = 1.0 - R / max(length(q.xz), 1e-9);
    return vec3(q.x * k, q.y, q.z * k);
}

// What a ray from p along unit dir sees, from the map: the distance stored along a direction
// from the centre gives the point the ray meets, whose direction from the centre is then
// looked up; fixed-point steps from "infinitely far" until the point moves by less than 0.1%
// (at most eight: a floor seen at a grazing angle takes more than three).
vec3 environment(vec3 p, vec3 dir, bool leaving) {
    vec3 pc = p - u_env_centre;
    vec3 q = dir;
    float t_prev = -1.0;
    if (leaving) {
        // A ray that leaves a solid (from near the map's centre, inside it) past the edge of
        // what the centre sees its way, a floor's far edge, meets nothing, which the steps
        // below cannot tell: it is marched through the map instead, in steps growing by 25%
        // from a fiftieth of what the centre sees that way, until a point lies just beyond
        // the surface the map holds in its direction, less than a step, which the point
        // before saw too (then the steps below start from there; a point hidden from the
        // centre, under a floor past its edge, is not a hit), or none does (then the ray
        // meets nothing: the background).
        float h = 0.02 * min(texture(u_env, dir).a, 1e6 * (1.0 + length(pc)));
        float s = h;
        bool crossed = false;
        float d_prev = -1.0;
        for (int k = 0; k < 40; ++k) {
            vec3 x = pc + s * dir;
            float d = texture(u_env, x).a;
            float behind = length(x) - d;
            if (behind >= 0.0 && behind < 1.5 * h && abs(d - d_prev) < 2.0 * h + 0.1 * d) {
                crossed = true;
                break;
            }
            d_prev = d;
            h *= 1.25;
            s += h;
        }
        if (!crossed) return u_background;
        t_prev = s;
        q = pc + s * dir;
    }
    for (int k = 0; k < 8; ++k) {
        float dist = texture(u_env, q).a;  // |hit - centre| of what q sees
        float b = dot(pc, dir);
        float disc = b * b - dot(pc, pc) + dist * dist;
        float t = disc > 0.0 ? -b + sqrt(disc) : 0.0;
        q = pc + t * dir;
        if (abs(t - t_prev) <= 1e-3 * t) break;
        t_prev = t;
    }
    return texture(u_env, q).rgb;
}

// Where a ray from ps along ts (inside the solid, its set's frame) leaves it, qs, and the
// outward normal there, ns: the solid of a transmitting range (u_solid).
void solid_exit(vec3 ps, vec3 ts, out vec3 qs, out vec3 ns) {
    if (u_solid == 1) {
        vec3 pc = ps - u_solid_sphere.xyz;
        float a = dot(ts, ts), b = dot(ts, pc);
        float disc = b * b - a * (dot(pc, pc) - u_solid_sphere.w * u_solid_sphere.w);
        ns = pc + (-b + sqrt(max(disc, 0.0))) / a * ts;
        qs = ns + u_solid_sphere.xyz;
    } else if (u_solid == 3) {
        // A torus: sphere tracing its distance (spec §13.7's surface) from inside, where it is
        // the safe step, to where it is crossed.
        vec3 tu = normalize(ts);
        float R = u_solid_radii.x, r = u_solid_radii.y, s = 1e-3 * r;
        vec3 q = ps - u_solid_sphere.xyz;
        // The tessellation's flat faces lie a little outside the saddle-shaped inner part:
        // from there the first steps go in.
        bool inside = false;
        for (int k = 0; k < 64; ++k) {
            float dist = torus_distance(q + s * tu, R, r);
            if (dist < -1e-4 * r)
                inside = true;
            else if (inside || dist > 0.05 * r)
                break;
            s += max(abs(dist), 1e-2 * r);
        }
        qs = q + s * tu + u_solid_sphere.xyz;
        ns = torus_normal(q + s * tu, R);
    } else {
        // A box: the nearest of the three far slabs.
        vec3 far = mix(u_solid_lo, u_solid_hi, step(0.0, ts));
        vec3 s3 = (far - ps) / ts;  // +inf or nan along a zero component
        float s = 1e30;
        int axis = 0;
        for (int k = 0; k < 3; ++k)
            if (ts[k] != 0.0 && s3[k] < s) {
                s = s3[k];
                axis = k;
            }
        qs = ps + max(s, 0.0) * ts;
        ns = vec3(0.0);
        ns[axis] = sign(ts[axis]);
    }
}
#endif

// Spec §7.3: bilinear with wrap; row 0 of the image is the top, v = 0 the bottom. The texture
// is uploaded with row 0 first and sampled with GL_REPEAT and GL_LINEAR, so t = 1 - v.
#ifdef RT_TEXTURES
vec3 texel(vec2 uv) { return u_textured ? texture(u_texture, vec2(uv.x, 1.0 - uv.y)).rgb : vec3(1.0); }
#else
vec3 texel(vec2 uv) { return vec3(1.0); }
#endif

#ifdef RT_TEXTURES
vec3 all_terms(vec3 t) { return u_texture_all ? t : vec3(1.0); }
#else
vec3 all_terms(vec3 t) { return vec3(1.0); }
#endif

#ifndef RT_ENV_PASS
// The trace pane's display transform (rt::display_transform in core/src/image/image.cpp): the
// colour times 2^exposure, then clamped (0), Reinhard's x / (1 + x) (1) or Narkowicz's fit of
// the ACES curve (2). The environment maps stay linear: what they hold is shaded again.
uniform float u_exposure_scale;
uniform int u_tonemap;
vec3 display(vec3 c) {
    vec3 x = c * u_exposure_scale;
    if (u_tonemap == 1) return max(x, vec3(0.0)) / (1.0 + max(x, vec3(0.0)));
    if (u_tonemap == 2) {
        x = max(x, vec3(0.0));
        return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
    }
    return x;
}
#endif

#ifdef RT_CLIP_PLANE
// A planar reflection's pass (planar.cpp): only what lies on the eye's side of the mirror.
uniform vec4 u_clip_plane;
uniform float u_clip_epsilon;
#endif
#ifdef RT_PLANAR
// Planar reflections: fragments on one of the planes (within its epsilon, the surface's own
// plane) read what the mirror shows from that plane's layer, at their own pixel.
uniform int u_planar_count;
uniform vec4 u_planar[4];
uniform float u_planar_epsilon[4];
uniform sampler2DArray u_planar_map;
uniform vec2 u_viewport;
int planar_layer(vec3 p, vec3 ng) {
    for (int k = 0; k < u_planar_count; ++k)
        if (abs(dot(vec4(p, 1.0), u_planar[k])) < u_planar_epsilon[k] &&
            abs(dot(ng, u_planar[k].xyz)) > 0.999)
            return k;
    return -1;
}
#endif

// Every light's terms at p with the normal n facing the ray d (the sum over lights above):
// t is the texel, ka and ks the textured K_A and K_S.
vec3 lights(vec3 p, vec3 n, vec3 d, vec3 t, vec3 ka, vec3 ks) {
    vec3 c = vec3(0.0);
#ifdef RT_SPECULAR
    vec3 r = d - 2.0 * dot(d, n) * n;
#endif
    for (int i = 0; i < u_light_count; ++i) {
        vec3 l;
        float f = 1.0;
#ifdef RT_DIRECTIONAL
        if (u_light_kind[i] == 0) {
            l = -u_light_direction[i];
        } else
#endif
        {
#if defined(RT_POINT) || defined(RT_SPOT)
            vec3 delta = u_light_position[i] - p;
            float dist = length(delta);
            if (dist <= 0.0) continue;
            l = delta / dist;
            float denom = u_light_atten[i].x + u_light_atten[i].y * dist + u_light_atten[i].z * dist * dist;
            if (denom <= 0.0) continue;
            f = 1.0 / denom;
#ifdef RT_SPOT
            if (u_light_kind[i] == 2) {
                float cos_a = dot(u_light_direction[i], -l);
                if (acos(clamp(cos_a, -1.0, 1.0)) > u_light_cutoff[i]) continue;
                if (u_light_exponent[i] != 0.0) f *= pow(max(0.0, cos_a), u_light_exponent[i]);
            }
#endif
#else
            continue;
#endif
        }
        c += ka * u_light_ambient[i] * f;  // spec §13.9: never shadowed, any N.L
        float ndl = dot(n, l);
        if (ndl <= 0.0) continue;
        vec3 sf = vec3(f);
#ifdef RT_SHADOWS
        sf *= visibility(i, p, n);
        if (sf == vec3(0.0)) continue;
#endif
#ifdef RT_SPECULAR
        float rdl = min(dot(r, l), 1.0);
        float spec = rdl > 0.0 ? pow(rdl, u_exponent) : 0.0;
        c += sf * (u_diffuse * t * u_light_diffuse[i] * ndl + ks * u_light_specular[i] * spec);
#else
        c += sf * (u_diffuse * t * u_light_diffuse[i] * ndl);
#endif
    }
    return c;
}

#ifdef RT_REFLECTIONS
// The local shading of a point of the fragment's material seen along d, the normal n facing
// the ray: what main() adds before reflection and refraction.
vec3 local_terms(vec3 p, vec3 n, vec3 d, vec3 t, vec3 ka, vec3 ks) {
    return u_emissive * all_terms(t) + ka * u_ambient_light + lights(p, n, d, t, ka, ks);
}
#endif

#if defined(RT_REFLECTIONS) && defined(RT_INNER_HITS)
// The light a ray leaving a torus at qs (its set's frame; from in the world) along dir brings
// back: through its hole or past its saddle the trace's ray meets the torus again, where the
// re-entry is shaded (the normal facing the ray), mirrors K_S times what the map shows, and
// lets T through its side to where it leaves again; a ray that misses the torus sees the map.
// `hits` counts the surfaces the depth limit still lets the trace meet on this path.
vec3 past_torus(vec3 qs, vec3 from, vec3 dir, int hits, vec3 t, vec3 ka, vec3 spec) {
    vec3 tu = normalize(mat3(u_set_from_world) * dir);
    float R = u_solid_radii.x, r = u_solid_radii.y;
    vec3 q = qs - u_solid_sphere.xyz;
    float s = 1e-3 * r, dist = 1.0;
    bool met = false;
    for (int k = 0; k < 128 && s < 4.0 * (R + r); ++k) {
        dist = torus_distance(q + s * tu, R, r);
        if (dist < 1e-4 * r && s > 2e-2 * r) {
            met = true;
            break;
        }
        s += max(dist, 1e-3 * r);
    }
    if (!met) return environment(from, dir, true);
    vec3 es = q + s * tu;  // the re-entry, from the torus's centre
    vec3 ne = torus_normal(es, R);
    vec3 e = (u_world_from_object * vec4(es + u_solid_sphere.xyz, 1.0)).xyz;
    vec3 n = normalize(u_normal_matrix * ne);  // outward: it faces the ray
    vec3 c = local_terms(e, n, dir, t, ka, spec);
    if (hits <= 1) return c;
    c += u_specular * environment(e, reflect(dir, n), false);
    vec3 in_dir = refract(dir, n, 1.0 / u_refind);
    if (in_dir == vec3(0.0)) return c;
    in_dir = normalize(in_dir);
    vec3 xs, nx;
    solid_exit(es + u_solid_sphere.xyz, mat3(u_set_from_world) * in_dir, xs, nx);
    vec3 x = (u_world_from_object * vec4(xs, 1.0)).xyz;
    vec3 n2 = normalize(u_normal_matrix * nx);
    c += u_transparent * local_terms(x, -n2, in_dir, t, ka, spec);
    vec3 out_dir = refract(in_dir, -n2, u_refind);
    if (hits > 2 && out_dir != vec3(0.0))
        c += u_transparent * u_transparent * environment(x, normalize(out_dir), true);
    return c;
}
#endif

void main() {
#ifdef RT_PLANAR
    // The surface's own plane, from the screen derivatives (before any discard).
    vec3 ng = normalize(cross(dFdx(v_world), dFdy(v_world)));
#endif
#ifdef RT_CLIP_PLANE
    if (dot(vec4(v_world, 1.0), u_clip_plane) < u_clip_epsilon) discard;
#endif
#ifdef RT_CSG
    if (v_leaf >= 0 && !csg_valid(v_leaf, v_set)) discard;
#endif
    vec3 d = normalize(v_world - u_eye);
    // The two-sided rule (spec §5): the side the ray meets is the geometric normal's, which is
    // the winding's (the tessellations wind counter-clockwise about it, and so do triangles in
    // their set): N = n_s when the front face is seen, else -n_s, whichever way n_s points.
    // A vertex normal against the winding then faces away and is dark, as in the trace.
    vec3 n = normalize(v_normal);
    if (gl_FrontFacing == u_mirrored) n = -n;
    vec3 t = texel(v_uv);
    vec3 ka = u_ambient * t;
    vec3 c = u_emissive * all_terms(t) + ka * u_ambient_light;
#ifdef RT_SPECULAR
    vec3 ks = u_specular * all_terms(t);
#else
    vec3 ks = vec3(0.0);
#endif
    c += lights(v_world, n, d, t, ka, ks);
#ifdef RT_REFLECTIONS
    if (u_env_on) {  // spec §7.4: the reflection weight K_S is not textured
#ifdef RT_PLANAR
        int k = planar_layer(v_world, ng);
        if (k >= 0)
            c += u_specular * texture(u_planar_map, vec3(gl_FragCoord.xy / u_viewport, float(k))).rgb;
        else
#endif
            c += u_specular * environment(v_world, d - 2.0 * dot(d, n) * n, false);
        if (u_transparent != vec3(0.0)) {
            // The eye sees the side facing it: entering, eta = 1 / refind.
            vec3 t_dir = refract(d, n, 1.0 / u_refind);
            if (t_dir != vec3(0.0)) {
                vec3 from = v_world, dir = normalize(t_dir), weight = u_transparent;
                if (u_solid != 0) {
                    // The second interface, where the refracted ray leaves the solid (in its
                    // set's frame, so also a sheared one in the world), bends it again (a ball
                    // of glass inverts what is behind it, as in the trace); the light crossing
                    // it is weighted by T at both surfaces. What the inner surface mirrors
                    // (K_S) meets the surface again: kInnerTraced hits inside, at most
                    // u_inner_hits (the depth limit), each shaded as the trace shades it, the
                    // last one's mirror image looked up.
                    vec3 ps = (u_set_from_world * vec4(v_world, 1.0)).xyz;
                    vec3 ts = mat3(u_set_from_world) * dir;
                    vec3 spec = u_specular * all_terms(t);
                    for (int hit = 1; hit <= kInnerTraced; ++hit) {
                        vec3 qs, ns;  // the exit and its outward normal, in the set's frame
                        solid_exit(ps, ts, qs, ns);
                        from = (u_world_from_object * vec4(qs, 1.0)).xyz;
                        vec3 n2 = normalize(u_normal_matrix * ns);  // outward at the exit
                        // Its local shading, the normal facing the ray (inward).
                        c += weight * local_terms(from, -n2, dir, t, ka, spec);
                        if (hit >= u_inner_hits) {  // the depth limit: no child rays
                            weight = vec3(0.0);
                            break;
                        }
                        vec3 out_dir = refract(dir, -n2, u_refind);
                        vec3 in_dir = reflect(dir, -n2);
                        vec3 inner = weight * u_specular;
                        if (out_dir != vec3(0.0)) {  // none leaves under total internal reflection
                            out_dir = normalize(out_dir);
#ifdef RT_INNER_HITS
                            if (u_solid == 3)
                                c += weight * u_transparent *
                                     past_torus(qs, from, out_dir, u_inner_hits - hit, t, ka, spec);
                            else
#endif
                                c += weight * u_transparent * environment(from, out_dir, true);
                        }
                        if (hit == kInnerTraced || max(inner.r, max(inner.g, inner.b)) < 0.001) {
                            // The mirror image seen past the solid, which its map leaves out.
                            c += inner * environment(from, in_dir, false);
                            weight = vec3(0.0);
                            break;
                        }
                        weight = inner;
                        dir = in_dir;
                        ps = qs;
                        ts = mat3(u_set_from_world) * dir;
                    }
                }
                if (weight != vec3(0.0)) c += weight * environment(from, dir, false);
            }
        }
    }
#endif
#ifdef RT_ENV_PASS
    frag_color = vec4(c, length(v_world - u_pass_centre));
#else
    frag_color = vec4(display(c), 1.0);
#endif
}
