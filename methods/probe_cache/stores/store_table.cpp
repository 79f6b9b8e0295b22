#include "methods/probe_cache/stores/store_table.h"

#include "methods/probe_cache/stores/cards/cards_store.h"
#include "methods/probe_cache/stores/dense_grid/dense_grid_store.h"
#include "methods/probe_cache/stores/hash_grid/hash_grid_store.h"
#include "methods/probe_cache/stores/mamba/mamba_store.h"

namespace gibench {

const std::vector<ProbeStoreInfo>& probeStoreTable() {
    static const std::vector<ProbeStoreInfo> table = {
        {"mamba", "probes in a sparse uniform grid stored as a two-level hash table (MAMBA)", "fine_cell_size",
         &mambaStoreParams, &createMambaStore},
        {"dense_grid", "probes found through a dense uniform grid over the scene (GIBS-like)", "cell_size",
         &denseGridStoreParams, &createDenseGridStore},
        {"cards", "probe texels on box-projected surface cards in an atlas (Lumen-like)", "texel_size",
         &cardsStoreParams, &createCardsStore},
        {"hash_grid", "the cell at a point is its cache entry, in one hash table with fingerprints (SHaRC-like)", "cell_size",
         &hashGridStoreParams, &createHashGridStore},
    };
    return table;
}

}  // namespace gibench
