#version 330 core
// Overlay lines (light markers, bounding boxes) in world space.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_color;
uniform mat4 u_clip_from_world;
out vec3 v_color;
void main() {
    v_color = a_color;
    gl_Position = u_clip_from_world * vec4(a_position, 1.0);
}
