#include "outputs/vmc_output.h"

#include "formats/arkit_format.h"

namespace th::outputs {

void VmcOutput::fill(OscBundle& bundle, const AvatarFrame& frame) {
  bundle.add("/VMC/Ext/OK").integer(1);
  bundle.add("/VMC/Ext/T").real(static_cast<float>(frame.timeSeconds));
  for (std::size_t k = 0; k < formats::kArkitNames.size(); ++k)
    bundle.add("/VMC/Ext/Blend/Val").string(formats::kArkitNames[k]).real(frame.arkit[k]);
  for (std::size_t k = 0; k < face::kVrmVowelNames.size(); ++k)
    bundle.add("/VMC/Ext/Blend/Val").string(face::kVrmVowelNames[k]).real(frame.vrm[k]);
  bundle.add("/VMC/Ext/Blend/Val").string("Blink_L").real(frame.blinkLeft());
  bundle.add("/VMC/Ext/Blend/Val").string("Blink_R").real(frame.blinkRight());
  bundle.add("/VMC/Ext/Blend/Apply");
  const Eigen::Quaternionf q = frame.unityHeadRotation();
  bundle.add("/VMC/Ext/Bone/Pos")
      .string("Head")
      .real(0.0f)
      .real(0.0f)
      .real(0.0f)
      .real(q.x())
      .real(q.y())
      .real(q.z())
      .real(q.w());
}

void VmcOutput::send(const AvatarFrame& frame) {
  OscBundle bundle;
  fill(bundle, frame);
  sender_.send(bundle);
}

OutputStatus VmcOutput::status() const {
  return sender_.statusAs("VMC");
}

}  // namespace th::outputs
