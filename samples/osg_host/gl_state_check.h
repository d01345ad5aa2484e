// gl_state_check.h — the proof that the plugin keeps OpenSceneGraph's state cache right: osg::State
// believes which program, buffers, textures, modes and attributes are current and skips a GL call when
// it thinks the value is already set, so a plugin that changed GL state behind its back would make OSG
// draw later geometry wrongly. After each plugin call the host compares the live GL state with what
// osg::State holds and counts every difference.
#pragma once

#include <string>
#include <vector>

#include <osg/GL>
#include <osg/RenderInfo>

namespace atmo::osg_host {

// One GL value and what osg::State believes it is.
struct StateEntry {
  std::string what;
  long long gl = 0, osg = 0;
};
using StateSnapshot = std::vector<StateEntry>;

// The live GL state next to osg::State's cache: program, VAO and buffers, framebuffers, viewport,
// capabilities, depth/blend/colour-mask/cull/polygon attributes, the active texture unit and every unit's
// texture and sampler bindings (32 units). OSG's State does not track framebuffers (its RenderStage binds
// them): expected_draw_fbo and expected_read_fbo say which the host knows to be bound. Restores the
// active texture unit it walks (the only GL state it changes).
StateSnapshot snapshot_gl_state(osg::RenderInfo& render_info, GLuint expected_draw_fbo, GLuint expected_read_fbo);

struct StateCheckTally {
  int checks = 0;       // snapshots compared after a call
  int values = 0;       // GL values compared with osg::State in them
  int mismatches = 0;   // values a call left different from OSG's belief (and from what GL held before it)
  int osg_own = 0;      // differences already in the baseline: OSG's own bookkeeping, not the plugin's
  std::vector<std::string> messages;      // the mismatches: where, what, GL's value, OSG's
  std::vector<std::string> osg_messages;  // OSG's own differences, each (what, value) once
};

// Tallies the snapshot after a call against OSG's belief; a difference the baseline (taken when OSG
// handed over, before any plugin call) had with the same GL value is OSG's own (counted apart), any other
// is a mismatch. Returns the mismatches.
int tally_call(const StateSnapshot& baseline, const StateSnapshot& after, const std::string& where,
               StateCheckTally* tally);

}  // namespace atmo::osg_host
