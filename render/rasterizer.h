// Draws the planar textured surfaces of a scene (simulator/surface.h) as a pinhole camera sees
// them: the scene radiance image, before the camera's own effects (render/image_formation.h).
//
// Model (docs/rendering.md): pixel (u, v) (origin at the centre of the top-left pixel,
// docs/conventions.md) sees along the ray K^-1 (u, v, 1); a surface's inverse depth 1/z and
// its texture coordinates times 1/z are affine in (u, v), so each convex polygon is
// rasterised by scanlines into a z-buffer of 1/z at pixel centres, then shaded with its
// texture through that homography. Anti-aliasing: a pixel whose 3x3 neighbourhood sees more
// than one surface gets the area-weighted mean of the surfaces over its square: exact
// (half-plane areas) where one straight boundary crosses the pixel, 8x8 supersampling where
// corners or several boundaries meet. A rendered edge therefore lies on the projected 3-D edge.
//
// Radiance of a surface point: albedo (1 + contrast pattern(s, t)) (0.6 + 0.35 n.L), a fixed
// light from above (L in world coordinates, y down), so that faces of different orientation
// differ in brightness even with equal albedo (the edges of a box show).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera.h"
#include "geometry/rigid3.h"
#include "render/texture.h"
#include "simulator/surface.h"

namespace slt {

class SurfaceRasterizer {
 public:
  // Keeps a reference to `surfaces`, which must outlive the rasteriser.
  explicit SurfaceRasterizer(const std::vector<Surface>& surfaces);

  // The radiance (CV_32FC1, width x height, values >= 0, about albedo x shading) of the scene seen by `camera`
  // at `cam_from_world`; pixels that see no surface are 0. `surface_ids` (CV_32SC1), when
  // given, receives the index of the surface seen through each pixel centre (-1: none).
  // Deterministic; safe to call from several threads at once.
  void Render(const PinholeCamera& camera, int width, int height, const Rigid3d& cam_from_world, cv::Mat* radiance,
              cv::Mat* surface_ids = nullptr) const;

  // Radiance factor of a surface's orientation, 0.6 + 0.35 n.L.
  static double Shading(const Eigen::Vector3d& normal_world);

 private:
  const std::vector<Surface>& surfaces_;
  // Per surface, the bounding sphere of its vertices (world): the field-of-view test.
  struct Bounds {
    Eigen::Vector3d centre;
    double radius;
  };
  std::vector<Bounds> bounds_;
  TextureBank textures_;
};

}  // namespace slt
