// The description at a render time (spec §14.6, §14.7).
#include "rt/scene/scene_time.h"

#include <cstdio>

namespace rt {

std::string time_name(const std::optional<SceneTime>& time) {
    if (!time) return "key 0";
    char buf[64];
    std::snprintf(buf, sizeof buf, "t = %.9g", time->seconds);
    return buf;
}

JointValues joint_values(const std::vector<KeyTrack>& tracks, const std::optional<SceneTime>& time,
                         Diagnostics* diag) {
    JointValues v;
    v.matrix.reserve(tracks.size());
    v.singular.reserve(tracks.size());
    for (const KeyTrack& track : tracks) {
        Mat4 m = track.keys.empty() ? Mat4(1.0) : track.keys[0];
        if (time) m = joint_matrix(track, time->seconds, time->interpolation, time->rotation);
        v.matrix.push_back(m);
        v.singular.push_back(singular_3x3(Mat3(m)) ? 1 : 0);
        if (v.singular.back() && diag)
            diag->warn(track.loc, "joint-singular",
                       "joint " + std::string("'") + track.name + "' is singular at " +
                           time_name(time) + "; its shapes are omitted");
    }
    return v;
}

SceneDesc scene_at_time(const SceneDesc& desc, const std::optional<SceneTime>& time,
                        Diagnostics* diag) {
    const JointValues values = joint_values(desc.tracks, time, diag);
    SceneDesc out = desc;
    out.tracks.clear();
    for (FileDesc& f : out.files) {
        std::vector<GroupDesc*> todo = {&f.root};
        auto push_operands = [&](std::vector<CsgDesc>& csgs) {
            for (CsgDesc& c : csgs)
                for (GroupDesc& o : c.operands) todo.push_back(&o);
        };
        while (!todo.empty()) {
            GroupDesc* g = todo.back();
            todo.pop_back();
            if (g->track >= 0) {
                const size_t k = static_cast<size_t>(g->track);
                g->matrix = values.matrix[k];
                g->track = -1;
                g->joint.clear();
                if (values.singular[k]) {
                    g->matrix = Mat4(1.0);  // an empty group: nothing of it is drawn
                    g->shapes.clear(), g->groups.clear(), g->instances.clear(), g->csgs.clear();
                }
            }
            for (GroupDesc& c : g->groups) todo.push_back(&c);
            push_operands(g->csgs);
            // CSG operands' own CSG children are reached through their groups' csgs.
        }
    }
    return out;
}

}  // namespace rt
