// A talking video tracked frame by frame: the 68 landmarks of the face in every frame (dlib, followed from
// frame to frame, smoothed over time), and the face model fitted to them (face_fit.h): the head's rotation and
// the jaw and lip FAPs, as training data is made from it.
//
//   th::tracking::Track track = th::tracking::trackVideo("clip.mpg");
//   th::tracking::fitTrack(track, faceModel);
//   th::tracking::writeTrackCsv("clip.csv", track);
//   double opening = th::tracking::mouthOpening(track.frames[10].landmarks);
//
// Frames where no face is found keep the landmarks of the nearest frame that has one (so every row is
// numbers) and are marked `found = false`. A video with no face in any frame is an error ("PATH: no face found
// in any of its N frames"); so is every error of VideoReader and LandmarkDetector.
//
// Thread contract: trackVideo may run on any thread; each call has its own reader and detector.
#pragma once

#include <filesystem>
#include <functional>
#include <vector>

#include "face/face_model.h"
#include "tracking/face_fit.h"
#include "tracking/landmarks.h"

namespace th::tracking {

struct TrackedFrame {
  double seconds = 0.0;  // frame f at f / fps
  bool found = false;    // a face was found in this frame
  Landmarks landmarks = Landmarks::Zero();
  FaceFit fit;  // after fitTrack
};

struct Track {
  std::filesystem::path video;
  double framesPerSecond = 0.0;
  int width = 0;
  int height = 0;
  std::vector<TrackedFrame> frames;
  int fullSearches = 0;         // frames that searched the whole image for the face (the rest followed it)
  std::vector<int> fittedFaps;  // the FAPs fitTrack fitted besides the head's (48-50); empty: not fitted
  int neutralFrame = -1;        // the frame fitTrack took as the speaker's rest face
  int framesFound() const;
};

struct TrackOptions {
  LandmarkOptions landmarks{};
  bool smooth = true;  // smoothLandmarks over the runs of found frames
};

// `progress(secondsDone)` is called after each frame (the video's seconds tracked so far), if given.
Track trackVideo(const std::filesystem::path& video, const TrackOptions& options = {},
                 const std::function<void(double)>& progress = {});

// Fits the face model to every frame (frames without a face take their neighbour's landmarks, as above), each
// from the previous frame's fit. The speaker's rest face (FaceFitter::calibrate) is the found frame with the
// lips closest together, unless `restFrame` (>= 0) names it. The fits go into track.frames[f].fit.
void fitTrack(Track& track, const face::FaceModel& face, const FitOptions& options = {}, int restFrame = -1);

// One row per frame: time_s, face (1 found, 0 held from a neighbour), then, if fitted, pitch_deg, yaw_deg,
// roll_deg (the head: FAPs 48-50 as degrees), fapN for each fitted FAP (FAPU counts) and residual_px; then
// x0, y0, ..., x67, y67 (pixels).
void writeTrackCsv(const std::filesystem::path& path, const Track& track);
// The same columns read back (for training from a track written earlier), fits included where the file has
// them. Errors name the file.
Track readTrackCsv(const std::filesystem::path& path);

// How far the lips are apart, as a share of the distance between the outer eye corners (36 and 45): the mean
// of the three inner-lip gaps 61-67, 62-66, 63-65. About 0 with the lips closed, 0.3-0.6 wide open.
double mouthOpening(const Landmarks& landmarks);
// How wide the mouth is, corner to corner (48-54), as a share of the same distance: it narrows for /u o w/ and
// widens for /i/.
double mouthWidth(const Landmarks& landmarks);

}  // namespace th::tracking
