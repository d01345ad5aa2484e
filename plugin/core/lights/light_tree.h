// light_tree.h — a bounding-volume hierarchy over a view's lights, so that
// the passes that must weigh every light against a cluster, a tile or the
// eye (the host's surfaces, the lights' diffusion in fog) walk a cut of the
// tree instead: the lights that matter there one by one, the rest as the
// nodes that hold them (lightcuts, Walter et al. 2005; Barnes & Hut 1986).
// A node is its lights' box, their weighted centre and their summed power:
// as one light it stands for them all where they are small and far.
//
// Built per view frame in O(n) after a sort by a key: the light's kind
// (omnidirectional, or its cone's axis to the nearest of 26 directions,
// one-way or two-way, narrow or wide) above its Morton code; split at the
// highest differing bit (Karras 2012): below the first levels a node holds
// lights of one kind in one cell of an octree, so its cones add up to one
// cone; ties in light order: the tree depends on the lights only. 65 536
// lights build in a few milliseconds.
// Pure; docs/FOG.md "Surfaces at scale".
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/fog/fog_frame.h"

namespace atmo::lights {

struct LightTree {
  struct Node {
    glm::vec3 lo{0.0f}, hi{0.0f};  // the box of its lights' positions (ENU relative to the eye, m)
    glm::vec3 centre{0.0f};        // their centre, weighted by peak intensity
    glm::vec3 power{0.0f};         // sum of intensity x the cone's mean over the sphere, cd per channel
    float peak = 0.0f;             // sum of the peak channel's intensity on the axis, cd (a bound: no cone)
    // Its lights' cones, as one: the omnidirectional lights' summed peak intensity, and the cone lights'
    // summed peak intensity on their axes, those axes' sum (each weighted by it, a two-way cone's axis
    // turned to a fixed half-space), the weighted sums of their cosines, two-way share and mean profile
    // (node_intensity_towards).
    float omni = 0.0f, cone = 0.0f;
    glm::vec3 axis_sum{0.0f};
    float cos_inner_sum = 0.0f, cos_outer_sum = 0.0f, two_way = 0.0f, mean_sum = 0.0f;
    float beta_min = 0.0f;         // the smallest effective extinction of its lights, 1/m
    float beta_mean = 0.0f;        // ... weighted as the centre
    float radius_m = 0.0f;         // a sphere about `centre` that holds every light of the node
    float variance_m2 = 0.0f;      // the weighted mean of |position - centre|^2
    uint32_t first = 0, count = 0; // its lights: order[first, first + count)
    int32_t left = -1, right = -1; // children; -1 in a leaf (one light)
    bool leaf() const { return left < 0; }
  };
  // nodes[0] is the root (empty tree: no nodes); the internal nodes first, then the n leaves in tree order.
  std::vector<Node> nodes;
  std::vector<uint32_t> order;  // light indices (into the frame) in tree order
  float dimmest_peak = 0.0f;    // the smallest peak intensity of a light that has one, cd (0: none)
  bool empty() const { return nodes.empty(); }
};

LightTree build_light_tree(const std::vector<fog::FrameLight>& lights);
// The same into *tree, reusing its storage (a view's tree, remade each frame).
void build_light_tree(const std::vector<fog::FrameLight>& lights, LightTree* tree);

// Its lights' summed irradiance at distance D from its centre, relative to
// all of them at the centre (I e^(-beta D) / D^2): the second-order term of
// the Taylor series, 1 + variance / 6 (beta^2 + 2 beta / D + 2 / D^2) (the
// Laplacian of e^(-beta r) / r^2), capped at 2 where the series fails (D
// about the node's size).
double node_spread_gain(const LightTree::Node& n, double distance_m, double beta_per_m);

// A node's cone lights as one cone (where n.cone > 0): their mean axis, mean cosines and two-way share, and
// how far their axes agree (|axis_sum| / cone: 1 for one axis, towards 0 for axes all round).
struct NodeCone {
  glm::vec3 axis{0.0f, 0.0f, 1.0f};
  float cos_inner = -2.0f, cos_outer = -2.0f, two_way = 0.0f, agree = 0.0f;
};
NodeCone node_cone(const LightTree::Node& n);

// A node's peak-channel intensity towards unit direction w, cd: its omnidirectional lights, and its cone
// lights as one cone on their mean axis with their mean cosines, the more so the more their axes agree (else
// their mean over the sphere). Exact for lights of one kind with one axis.
float node_intensity_towards(const LightTree::Node& n, const glm::vec3& w);

// Distance from p to the box [lo, hi] (0 inside).
float distance_to_box(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi);

}  // namespace atmo::lights
