#include "pipeline/head_style_source.h"

#include "animation/head_style.h"

namespace th::pipeline {

void resolveHeadStyle(HeadMotionOptions& head, IdleOptions& idle, const animation::HeadModel& model) {
  if (head.style.empty() || head.fittedStyle) return;
  useHeadStyle(animation::headStyleFromFile(model, head.style), head, idle);
}

}  // namespace th::pipeline
