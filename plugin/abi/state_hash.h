// state_hash.h — get_state_hash's parts (AtmoStateHashPart): a hash of every
// input and cached state that changes what a view's next pass draws, so the
// channels of a multi-channel host (and tests) can check they agree
// (docs/MULTI_CHANNEL.md). History counters (versions, serials) never enter
// it: two channels with the same inputs agree even if one started later.
#pragma once

#include <cstdint>

#include "atmo/atmo.h"

struct AtmoContext_T;
struct AtmoView_T;

namespace atmo::abi {

// What the content hashes were made for (the inputs' version counters): the
// lights, the occluders and the cloud field are hashed once a change.
struct StateHashCache {
  uint64_t lights_version = ~0ull, lights_hash = 0;
  uint64_t occluders_version = ~0ull, occluders_hash = 0;
  uint64_t field_version = ~0ull, field_hash = 0;
};

// parts[k] for k < ATMO_STATE_HASH_PART_COUNT, of the state as it is now (the
// caller settles what is due first).
void state_hash_parts(AtmoContext_T* context, const AtmoView_T& view, uint64_t parts[ATMO_STATE_HASH_PART_COUNT]);

// The parts FRAME .. OCCLUDERS combined (AtmoStateHash.hash).
uint64_t combined_state_hash(const uint64_t parts[ATMO_STATE_HASH_PART_COUNT]);

}  // namespace atmo::abi
