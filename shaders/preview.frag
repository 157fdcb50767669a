#version 330 core
// The tracer's local shading (spec §7.1-7.3) without shadows, reflection or refraction:
// emissive + ambient * texel * A + for each light with N.L > 0:
//   I_l * (kd * texel * N.L + ks * (R_v.L)^e), the two-sided normal facing the eye.
// Lights: point and spot attenuate by 1 / (ca + la d + qa d^2); spots cut off by angle and
// fall off as cos^p (factor 1 when p = 0); a non-positive denominator gives no light.
const int kMaxLights = 16;

in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;

uniform vec3 u_eye;
uniform vec3 u_ambient_light;
uniform vec3 u_emissive;
uniform vec3 u_ambient;
uniform vec3 u_diffuse;
uniform vec3 u_specular;
uniform float u_exponent;
uniform bool u_textured;
uniform sampler2D u_texture;

uniform int u_light_count;
uniform int u_light_kind[kMaxLights];  // 0 directional, 1 point, 2 spot
uniform vec3 u_light_color[kMaxLights];
uniform vec3 u_light_position[kMaxLights];
uniform vec3 u_light_direction[kMaxLights];  // unit: travel (directional) or axis (spot)
uniform vec3 u_light_atten[kMaxLights];      // ca, la, qa
uniform float u_light_cutoff[kMaxLights];
uniform float u_light_exponent[kMaxLights];

out vec4 frag_color;

// Spec §7.3: bilinear with wrap; row 0 of the image is the top, v = 0 the bottom. The texture
// is uploaded with row 0 first and sampled with GL_REPEAT and GL_LINEAR, so t = 1 - v.
vec3 texel(vec2 uv) { return texture(u_texture, vec2(uv.x, 1.0 - uv.y)).rgb; }

void main() {
    vec3 d = normalize(v_world - u_eye);
    vec3 n = normalize(v_normal);
    if (dot(d, n) > 0.0) n = -n;  // two-sided rule (spec §5)
    vec3 t = u_textured ? texel(v_uv) : vec3(1.0);
    vec3 c = u_emissive + u_ambient * t * u_ambient_light;
    vec3 r = d - 2.0 * dot(d, n) * n;
    for (int i = 0; i < u_light_count; ++i) {
        vec3 l;
        vec3 intensity = u_light_color[i];
        if (u_light_kind[i] == 0) {
            l = -u_light_direction[i];
        } else {
            vec3 delta = u_light_position[i] - v_world;
            float dist = length(delta);
            if (dist <= 0.0) continue;
            l = delta / dist;
            float denom = u_light_atten[i].x + u_light_atten[i].y * dist + u_light_atten[i].z * dist * dist;
            if (denom <= 0.0) continue;
            float factor = 1.0 / denom;
            if (u_light_kind[i] == 2) {
                float cos_a = dot(u_light_direction[i], -l);
                if (acos(clamp(cos_a, -1.0, 1.0)) > u_light_cutoff[i]) continue;
                if (u_light_exponent[i] != 0.0) factor *= pow(max(0.0, cos_a), u_light_exponent[i]);
            }
            intensity *= factor;
        }
        float ndl = dot(n, l);
        if (ndl <= 0.0) continue;
        float rdl = dot(r, l);
        float spec = rdl > 0.0 ? pow(rdl, u_exponent) : 0.0;
        c += intensity * (u_diffuse * t * ndl + u_specular * spec);
    }
    frag_color = vec4(c, 1.0);
}
