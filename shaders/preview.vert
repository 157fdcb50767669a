#version 330 core
// The preview's vertices: world position from the instance transform, normal by its inverse
// transpose (spec §4.1), texture coordinates unchanged.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;

uniform mat4 u_world_from_object;
uniform mat3 u_normal_matrix;
uniform mat4 u_clip_from_world;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
#ifdef RT_CSG
layout(location = 3) in float a_leaf;  // CSG leaf (GeometrySet::csg.leaves), -1: none
flat out int v_leaf;
out vec3 v_set;  // the position in the set's frame, where the CSG trees are
#endif

void main() {
    vec4 world = u_world_from_object * vec4(a_position, 1.0);
    v_world = world.xyz;
    v_normal = u_normal_matrix * a_normal;
    v_uv = a_uv;
#ifdef RT_CSG
    v_leaf = int(a_leaf);
    v_set = a_position;
#endif
    gl_Position = u_clip_from_world * world;
}
