#pragma once
// Probe store "cards" (Lumen-like surface cache): rectangular arrays of probe texels laid on each
// mesh by axis-aligned box projection, packed into one atlas, with a per-frame budget of texel
// updates. Placement, lookup and memory are described at the top of cards_store.cpp.

#include "methods/probe_cache/probe_store.h"

#include <memory>

namespace gibench {

const ParamTable& cardsStoreParams();
// Cards are laid out in ProbeStore::prepare(), which throws InputError when the atlas would
// exceed max_atlas_texels.
std::unique_ptr<ProbeStore> createCardsStore(Params& params);

}  // namespace gibench
