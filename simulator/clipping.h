// Clipping segments to what a camera sees: the half-space in front of it and the image.
#pragma once

#include <Eigen/Core>

namespace slt {

// Cuts the segment p-q (camera coordinates) at the plane z = min_depth and keeps the part in
// front. Returns false, leaving p and q unspecified, when no part is in front.
bool ClipSegmentToDepth(double min_depth, Eigen::Vector3d* p, Eigen::Vector3d* q);

// Clips the segment a-b (pixels) to the image rectangle [0, width-1] x [0, height-1], the
// rectangle of StereoRig::InImage (Liang-Barsky). Returns false, leaving a and b unspecified,
// when no part of the segment is inside.
bool ClipSegmentToImage(int width, int height, Eigen::Vector2d* a, Eigen::Vector2d* b);

}  // namespace slt
