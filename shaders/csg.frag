#version 330 core
// Spec §13.8's valid surfaces for the preview and its shadow maps: linked into the programs
// compiled with RT_CSG (Preview::program_for, Preview::render_shadow_maps), which discard the
// fragments of CSG leaves for which csg_valid() is false.
// The instance's set's CSG trees as RGBA32F texels (Preview::load, csg_preview.cpp):
//   node n:  [nodes + 2n] = (kind, first, count, parent), [nodes + 2n + 1].x = subtree_first
//            kind 0 leaf (first: its leaf), 1 union, 2 intersection, 3 difference (A, B),
//            4 list (filters nothing), 5 empty; parent -1 at a root; post-order per tree
//   child i: [children + i].x = node
//   leaf l:  [leaves + 6l] = (shape kind, tolerance, node, 0), [+1..+3] rows of leaf_from_set,
//            [+4] = (centre, a), [+5] = (b, c, 0, 0): sphere a = r; box (a, b, c) = half sides;
//            cylinder, cone a = r, b = h; torus a = tube, b = ring; triangles are never inside
// The texels are rows of kCsgRow in a 2D texture (GLSL ES 3.00 has no buffer textures).
uniform sampler2D u_csg;
uniform int u_csg_nodes, u_csg_children, u_csg_leaves;
const int kMaxCsgNodes = 64;  // a larger tree is drawn unfiltered
const int kCsgRow = 1024;     // Preview's kCsgRow

vec4 csg_texel(int i) { return texelFetch(u_csg, ivec2(i % kCsgRow, i / kCsgRow), 0); }

// Spec §13.8's sign function of leaf l at p (set frame): < 0 inside, > 0 outside.
float csg_sign(int l, vec3 p) {
    int base = u_csg_leaves + 6 * l;
    int kind = int(csg_texel(base).x);
    vec4 p4 = vec4(p, 1.0);
    vec4 c = csg_texel(base + 4);
    vec4 e = csg_texel(base + 5);
    vec3 q = vec3(dot(csg_texel(base + 1), p4), dot(csg_texel(base + 2), p4),
                  dot(csg_texel(base + 3), p4)) - c.xyz;
    if (kind == 0) return length(q) - c.w;
    if (kind == 1) return max(abs(q.x) - c.w, max(abs(q.y) - e.x, abs(q.z) - e.y));
    float rho = length(q.xz);
    if (kind == 2) return max(rho - c.w, abs(q.y) - 0.5 * e.x);
    if (kind == 3) return max(rho - c.w * (0.5 * e.x - q.y) / e.x, abs(q.y) - 0.5 * e.x);
    if (kind == 5) return length(vec2(rho - e.x, q.y)) - c.w;
    return 1e30;  // triangles: never inside
}

// Whether the surface point p of leaf l is a surface of the scene: every CSG node on the path to
// the root accepts it (spec §13.8, "valid surfaces").
bool csg_valid(int l, vec3 p) {
    int leaf_node = int(csg_texel(u_csg_leaves + 6 * l).z);
    int root = leaf_node;
    for (int k = 0; k < kMaxCsgNodes; ++k) {
        int up = int(csg_texel(u_csg_nodes + 2 * root).w);
        if (up < 0) break;
        root = up;
    }
    int first = int(csg_texel(u_csg_nodes + 2 * root + 1).x);
    if (root - first >= kMaxCsgNodes) return true;
    // Every node's "strictly inside" and "inside or on" at p, children before parents.
    bool si[kMaxCsgNodes], io[kMaxCsgNodes];
    for (int n = first; n <= root; ++n) {
        vec4 nd = csg_texel(u_csg_nodes + 2 * n);
        int kind = int(nd.x), a = int(nd.y), count = int(nd.z);
        bool s = false, o = false;
        if (kind == 0) {
            float sg = csg_sign(a, p);
            float eps = csg_texel(u_csg_leaves + 6 * a).y;
            s = sg < -eps;
            o = sg <= eps;
        } else if (kind == 1 || kind == 4 || kind == 2) {
            bool all = kind == 2;
            s = all && count > 0;
            o = s;
            for (int i = 0; i < count; ++i) {
                int c = int(csg_texel(u_csg_children + a + i).x) - first;
                s = all ? (s && si[c]) : (s || si[c]);
                o = all ? (o && io[c]) : (o || io[c]);
            }
        } else if (kind == 3) {
            int ca = int(csg_texel(u_csg_children + a).x) - first;
            int cb = int(csg_texel(u_csg_children + a + 1).x) - first;
            s = si[ca] && !io[cb];
            o = io[ca] && !si[cb];
        }
        si[n - first] = s;
        io[n - first] = o;
    }
    // From the leaf up: each node tests its other children.
    int cur = leaf_node;
    for (int k = 0; k < kMaxCsgNodes; ++k) {
        vec4 cn = csg_texel(u_csg_nodes + 2 * cur);
        int node = int(cn.w);
        if (node < 0) break;
        vec4 nd = csg_texel(u_csg_nodes + 2 * node);
        int kind = int(nd.x), a = int(nd.y), count = int(nd.z);
        if (kind == 3) {
            int ca = int(csg_texel(u_csg_children + a).x);
            int cb = int(csg_texel(u_csg_children + a + 1).x);
            if (cur == ca && si[cb - first]) return false;  // A's surface inside B
            if (cur == cb && !si[ca - first]) return false;  // B's surface outside A
        } else if (kind == 1 || kind == 2) {
            for (int i = 0; i < count; ++i) {
                int c = int(csg_texel(u_csg_children + a + i).x);
                if (c == cur) continue;
                if (kind == 1 && si[c - first]) return false;
                if (kind == 2 && !io[c - first]) return false;
            }
        }
        cur = node;
    }
    return true;
}
