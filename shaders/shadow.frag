#version 330 core
// Shadow-map depth (used with preview.vert): for point and spot lights the distance to the light
// over the far distance (the same quantity preview.frag compares), for directional lights the
// orthographic depth as it is. With RT_TRANSMIT, the transmittance maps of transparent surfaces
// instead (Preview::render_transmit_maps).
in vec3 v_world;
uniform bool u_radial;
uniform vec3 u_light_position;
uniform float u_far;
#ifdef RT_CSG
flat in int v_leaf;  // as in preview.frag: CSG leaves cast shadows only where they are surfaces
in vec3 v_set;
bool csg_valid(int l, vec3 p);  // csg.frag
#endif
#ifdef RT_TRANSMIT
// The transmittance maps (RT_TRANSMIT): the surface's T, multiplied into the map by blending,
// and as alpha the same depth, of which blending keeps the smallest.
uniform vec3 u_transmit;
out vec4 frag_color;
#endif
void main() {
#ifdef RT_CSG
    if (v_leaf >= 0 && !csg_valid(v_leaf, v_set)) discard;
#endif
    float depth = u_radial ? min(distance(v_world, u_light_position) / u_far, 1.0) : gl_FragCoord.z;
#ifdef RT_TRANSMIT
    frag_color = vec4(u_transmit, depth);
#else
    gl_FragDepth = depth;
#endif
}
