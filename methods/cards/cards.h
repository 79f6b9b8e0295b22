#pragma once
// Method "cards": the probe-cache pipeline (core/probe_pipeline.h) with probe texels on box-projected surface cards in an atlas (Lumen-like).

#include "core/method.h"

namespace gibench {

const ParamTable& cardsParams();
std::unique_ptr<Method> createCards(Params& params);

}  // namespace gibench
