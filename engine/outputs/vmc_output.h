// The VMC protocol as a Performer (https://protocol.vmc.info): each frame one OSC bundle to the Marionette
// (VSeeFace, VMagicMirror, Virtual Motion Capture, the Unity, Unreal and Blender receivers) holding
//   /VMC/Ext/OK 1                               the avatar is loaded
//   /VMC/Ext/T TIME                             the frame's time, seconds
//   /VMC/Ext/Blend/Val NAME VALUE               ARKit's 52 (their names as Apple spells them, for "perfect
//                                               sync" avatars), VRM's A I U E O, Blink_L, Blink_R
//   /VMC/Ext/Blend/Apply                        apply the values above
//   /VMC/Ext/Bone/Pos Head px py pz qx qy qz qw the head's rotation, local, in Unity's convention (left-handed,
//                                               y up, z forward); position 0 (the avatar's rig places the head)
// Thread contract: as LiveOutput.
#pragma once

#include "outputs/live_output.h"
#include "outputs/osc_sender.h"

namespace th::outputs {

class VmcOutput final : public LiveOutput {
 public:
  explicit VmcOutput(UdpEndpoint endpoint) : sender_(std::move(endpoint)) {}
  void send(const AvatarFrame& frame) override;
  OutputStatus status() const override;
  static void fill(OscBundle& bundle, const AvatarFrame& frame);  // the bundle of one frame

 private:
  OscSender sender_;
};

}  // namespace th::outputs
