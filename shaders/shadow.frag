#version 330 core
// Shadow-map depth (used with preview.vert): for point and spot lights the distance to the light
// over the far distance (the same quantity preview.frag compares), for directional lights the
// orthographic depth as it is.
in vec3 v_world;
uniform bool u_radial;
uniform vec3 u_light_position;
uniform float u_far;
void main() {
    gl_FragDepth = u_radial ? min(distance(v_world, u_light_position) / u_far, 1.0) : gl_FragCoord.z;
}
