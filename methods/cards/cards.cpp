#include "methods/cards/cards.h"

#include "core/probe_pipeline.h"
#include "methods/cards/cards_store.h"

namespace gibench {

const ParamTable& cardsParams() {
    static const ParamTable table = withPipelineParams(kCardsStoreParams);
    return table;
}

std::unique_ptr<Method> createCards(Params& params) { return createProbeCacheMethod(params, &createCardsStore); }

}  // namespace gibench
