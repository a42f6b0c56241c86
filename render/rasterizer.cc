#include "render/rasterizer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace slt {
namespace {

// Polygons are cut at this depth (m) before projection.
constexpr double kNearDepth = 1e-3;
// A near-clipped convex polygon has at most one vertex more than it had; the scenes use
// triangles and quads, MakeSurface allows more.
constexpr int kMaxVertices = 16;
// Samples per side of the supersampling grid where corners or several boundaries meet.
constexpr int kSupersample = 8;
constexpr double kSpanSlack = 1e-6;

using Polygon2d = std::array<Eigen::Vector2d, kMaxVertices>;

// One surface as the current camera sees it.
struct Projected {
  int surface = -1;
  int vertex_count = 0;
  Polygon2d pixels;
  // Edge lines a u + b v + c, (a, b) unit, <= 0 inside.
  std::array<Eigen::Vector3d, kMaxVertices> edges;
  Eigen::Vector3d inverse_depth;  // 1/z = inverse_depth . (u, v, 1)
  Eigen::Vector3d s_times_w, t_times_w;  // texture coordinates (in scale units) times 1/z
  double brightness = 0.0;
  double contrast = 0.0;
  TexturePattern pattern = TexturePattern::kFlat;

  double InverseDepth(double u, double v) const {
    return inverse_depth[0] * u + inverse_depth[1] * v + inverse_depth[2];
  }
  bool Contains(double u, double v) const {
    for (int i = 0; i < vertex_count; ++i) {
      if (edges[i][0] * u + edges[i][1] * v + edges[i][2] > 0.0) return false;
    }
    return true;
  }
};

// Texture anti-aliasing: where a pixel spans `footprint` scale units of a texture (far or
// grazing surfaces) its finest features (0.5 units) would alias into false gradients, so the
// pattern's contrast fades as 1 / (1 + (footprint / 0.2)^2), a cheap stand-in for mipmapping.
inline double TextureFade(double footprint) {
  const double r = footprint / 0.2;
  return 1.0 / (1.0 + r * r);
}

// The light's direction (towards it) in the world: above (y down), a little to the right and
// behind the camera at frame 0.
const Eigen::Vector3d kLight = Eigen::Vector3d(0.3, -0.85, -0.43).normalized();

// A convex polygon clipped to the half-plane line . (u, v, 1) <= 0, in place.
struct Clip {
  std::array<Eigen::Vector2d, kMaxVertices + 4> v;
  int n = 0;

  void Square(double u, double w) {
    n = 4;
    v[0] = {u - 0.5, w - 0.5};
    v[1] = {u + 0.5, w - 0.5};
    v[2] = {u + 0.5, w + 0.5};
    v[3] = {u - 0.5, w + 0.5};
  }
  void Cut(const Eigen::Vector3d& line) {
    std::array<Eigen::Vector2d, kMaxVertices + 4> out;
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d& p = v[i];
      const Eigen::Vector2d& q = v[(i + 1) % n];
      const double dp = line[0] * p.x() + line[1] * p.y() + line[2];
      const double dq = line[0] * q.x() + line[1] * q.y() + line[2];
      if (dp <= 0.0) out[m++] = p;
      if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) out[m++] = p + (dp / (dp - dq)) * (q - p);
      if (m >= kMaxVertices + 3) break;
    }
    v = out;
    n = m;
  }
  // Area and centroid (shoelace).
  double Area(Eigen::Vector2d* centroid) const {
    double twice_area = 0.0;
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d& p = v[i];
      const Eigen::Vector2d& q = v[(i + 1) % n];
      const double cross = p.x() * q.y() - q.x() * p.y();
      twice_area += cross;
      c += cross * (p + q);
    }
    if (centroid != nullptr && twice_area != 0.0) *centroid = c / (3.0 * twice_area);
    return 0.5 * std::abs(twice_area);
  }
};

// Cuts the polygon at z = kNearDepth; returns the vertex count of what is in front.
int ClipToNearPlane(const Eigen::Vector3d* in, int n, Eigen::Vector3d* out) {
  int m = 0;
  for (int i = 0; i < n && m < kMaxVertices; ++i) {
    const Eigen::Vector3d& p = in[i];
    const Eigen::Vector3d& q = in[(i + 1) % n];
    const bool p_in = p.z() >= kNearDepth, q_in = q.z() >= kNearDepth;
    if (p_in) out[m++] = p;
    if (p_in != q_in && m < kMaxVertices) {
      const double t = (kNearDepth - p.z()) / (q.z() - p.z());
      out[m] = p + t * (q - p);
      out[m++].z() = kNearDepth;
    }
  }
  return m;
}

}  // namespace

double SurfaceRasterizer::Shading(const Eigen::Vector3d& normal_world) { return 0.6 + 0.35 * normal_world.dot(kLight); }

SurfaceRasterizer::SurfaceRasterizer(const std::vector<Surface>& surfaces) : surfaces_(surfaces) {
  bounds_.reserve(surfaces_.size());
  for (const Surface& s : surfaces_) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& v : s.vertices) centre += v;
    centre /= static_cast<double>(s.vertices.size());
    double radius = 0.0;
    for (const Eigen::Vector3d& v : s.vertices) radius = std::max(radius, (v - centre).norm());
    bounds_.push_back({centre, radius});
  }
}

void SurfaceRasterizer::Render(const PinholeCamera& camera, int width, int height, const Rigid3d& cam_from_world,
                               cv::Mat* radiance, cv::Mat* surface_ids) const {
  // The work buffers of this thread, kept between calls: a street's frame would otherwise
  // allocate (and page in) megabytes per image.
  thread_local std::vector<Projected> polygons;
  thread_local std::vector<float> inverse_depth;
  thread_local std::vector<unsigned char> mixed_mask;
  thread_local cv::Mat ids;
  polygons.clear();

  // 1. Every surface facing the camera and within the field of view (its bounding sphere
  // against the four planes through the eye and the image's borders, widened by a pixel), cut
  // at the near plane and projected.
  const Eigen::Vector3d eye = cam_from_world.Center();
  std::array<Eigen::Vector3d, 4> side_planes;  // camera frame, through the origin, inward normals
  {
    const double u0 = (-1.0 - camera.cx) / camera.fx, u1 = (width - camera.cx) / camera.fx;
    const double v0 = (-1.0 - camera.cy) / camera.fy, v1 = (height - camera.cy) / camera.fy;
    side_planes = {Eigen::Vector3d(1.0, 0.0, -u0).normalized(), Eigen::Vector3d(-1.0, 0.0, u1).normalized(),
                   Eigen::Vector3d(0.0, 1.0, -v0).normalized(), Eigen::Vector3d(0.0, -1.0, v1).normalized()};
  }
  std::array<Eigen::Vector3d, kMaxVertices> in_camera, clipped;
  for (std::size_t k = 0; k < surfaces_.size(); ++k) {
    const Surface& surface = surfaces_[k];
    const Eigen::Vector3d centre = cam_from_world * bounds_[k].centre;
    const double radius = bounds_[k].radius;
    if (centre.z() + radius < kNearDepth || side_planes[0].dot(centre) < -radius ||
        side_planes[1].dot(centre) < -radius || side_planes[2].dot(centre) < -radius ||
        side_planes[3].dot(centre) < -radius) {
      continue;
    }
    const int n = static_cast<int>(std::min<std::size_t>(surface.vertices.size(), kMaxVertices - 1));
    Eigen::Vector3d normal = surface.normal;
    const double facing = normal.dot(eye - surface.vertices[0]);
    if (facing <= 0.0) {
      if (!surface.two_sided) continue;
      normal = -normal;
    }
    for (int i = 0; i < n; ++i) in_camera[i] = cam_from_world * surface.vertices[i];
    const int m = ClipToNearPlane(in_camera.data(), n, clipped.data());
    if (m < 3) continue;
    Projected p;
    p.surface = static_cast<int>(k);
    p.vertex_count = m;
    double u_min = std::numeric_limits<double>::infinity(), u_max = -u_min, v_min = u_min, v_max = -u_min;
    for (int i = 0; i < m; ++i) {
      p.pixels[i] = camera.Project(clipped[i]);
      u_min = std::min(u_min, p.pixels[i].x());
      u_max = std::max(u_max, p.pixels[i].x());
      v_min = std::min(v_min, p.pixels[i].y());
      v_max = std::max(v_max, p.pixels[i].y());
    }
    if (u_max < -1.0 || v_max < -1.0 || u_min > width || v_min > height) continue;
    // Orientation of the projected polygon: the edge lines point outwards either way round.
    double twice_area = 0.0;
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector2d &a = p.pixels[i], &b = p.pixels[(i + 1) % m];
      twice_area += a.x() * b.y() - b.x() * a.y();
    }
    if (twice_area == 0.0) continue;
    const double orientation = twice_area > 0.0 ? 1.0 : -1.0;
    for (int i = 0; i < m; ++i) {
      const Eigen::Vector2d &a = p.pixels[i], &b = p.pixels[(i + 1) % m];
      Eigen::Vector2d outward(b.y() - a.y(), a.x() - b.x());
      outward *= orientation / outward.norm();
      p.edges[i] = Eigen::Vector3d(outward.x(), outward.y(), -outward.dot(a));
    }
    // The plane n . X = d in the camera; a pixel's ray is X = z r(u, v), r = K^-1 (u, v, 1), so
    // 1/z = n . r / d, affine in (u, v). Texture coordinates: s = a . X - a . o = (a . r) / w - a . o.
    const Eigen::Vector3d n_cam = cam_from_world.rotation * normal;
    const double d = n_cam.dot(clipped[0]);
    // r = (u / fx - cx / fx, v / fy - cy / fy, 1): a linear map of (u, v, 1).
    Eigen::Matrix3d ray = Eigen::Matrix3d::Zero();
    ray << 1.0 / camera.fx, 0.0, -camera.cx / camera.fx, 0.0, 1.0 / camera.fy, -camera.cy / camera.fy, 0.0, 0.0, 1.0;
    p.inverse_depth = (n_cam.transpose() * ray).transpose() / d;
    const SurfaceTexture& texture = surface.texture;
    const double inv_scale = 1.0 / texture.scale_m;
    // Each surface starts at its own place in the tile (its seed), kept whole texels.
    const double offset_s = static_cast<double>(texture.seed & 0xffffu) / 256.0;
    const double offset_t = static_cast<double>((texture.seed >> 16) & 0xffffu) / 256.0;
    const Eigen::Vector3d origin = cam_from_world * surface.texture_origin;
    const Eigen::Vector3d axis_s = cam_from_world.rotation * surface.axis_s;
    const Eigen::Vector3d axis_t = cam_from_world.rotation * surface.axis_t;
    p.s_times_w = inv_scale * (axis_s.transpose() * ray).transpose() +
                  (offset_s - inv_scale * axis_s.dot(origin)) * p.inverse_depth;
    p.t_times_w = inv_scale * (axis_t.transpose() * ray).transpose() +
                  (offset_t - inv_scale * axis_t.dot(origin)) * p.inverse_depth;
    p.brightness = texture.albedo * Shading(normal);
    p.contrast = texture.contrast;
    p.pattern = texture.pattern;
    polygons.push_back(p);
  }

  // 2. Scanline z-buffer of 1/z at pixel centres; ties keep the first surface.
  ids.create(height, width, CV_32SC1);
  ids.setTo(-1);
  inverse_depth.assign(static_cast<std::size_t>(width) * height, 0.0f);
  for (std::size_t k = 0; k < polygons.size(); ++k) {
    const Projected& p = polygons[k];
    double v_min = std::numeric_limits<double>::infinity(), v_max = -v_min;
    for (int i = 0; i < p.vertex_count; ++i) {
      v_min = std::min(v_min, p.pixels[i].y());
      v_max = std::max(v_max, p.pixels[i].y());
    }
    // Spans are widened by kSpanSlack px, so that a pixel centre on the edge shared by two
    // polygons is not missed by both through rounding (the z-buffer settles the overlap).
    const int y0 = std::max(0, static_cast<int>(std::ceil(v_min - kSpanSlack)));
    const int y1 = std::min(height - 1, static_cast<int>(std::floor(v_max + kSpanSlack)));
    for (int y = y0; y <= y1; ++y) {
      double x_left = std::numeric_limits<double>::infinity(), x_right = -x_left;
      for (int i = 0; i < p.vertex_count; ++i) {
        const Eigen::Vector2d &a = p.pixels[i], &b = p.pixels[(i + 1) % p.vertex_count];
        if (std::min(a.y(), b.y()) > y + kSpanSlack || std::max(a.y(), b.y()) < y - kSpanSlack) continue;
        if (a.y() == b.y()) {
          x_left = std::min({x_left, a.x(), b.x()});
          x_right = std::max({x_right, a.x(), b.x()});
        } else {
          const double f = std::clamp((y - a.y()) / (b.y() - a.y()), 0.0, 1.0);
          const double x = a.x() + f * (b.x() - a.x());
          x_left = std::min(x_left, x);
          x_right = std::max(x_right, x);
        }
      }
      const int x0 = std::max(0, static_cast<int>(std::ceil(x_left - kSpanSlack)));
      const int x1 = std::min(width - 1, static_cast<int>(std::floor(x_right + kSpanSlack)));
      if (x0 > x1) continue;
      float* depth_row = inverse_depth.data() + static_cast<std::size_t>(y) * width;
      int* id_row = ids.ptr<int>(y);
      const double w_row = p.inverse_depth[1] * y + p.inverse_depth[2];
      for (int x = x0; x <= x1; ++x) {
        const float w = static_cast<float>(p.inverse_depth[0] * x + w_row);
        if (w > depth_row[x]) {
          depth_row[x] = w;
          id_row[x] = static_cast<int>(k);
        }
      }
    }
  }

  // 3. Shading at every pixel centre.
  const auto colour = [&](const Projected& p, double u, double v) {
    const double w = p.InverseDepth(u, v);
    if (p.contrast == 0.0 || !(w > 0.0)) return p.brightness;
    const double s = (p.s_times_w[0] * u + p.s_times_w[1] * v + p.s_times_w[2]) / w;
    const double t = (p.t_times_w[0] * u + p.t_times_w[1] * v + p.t_times_w[2]) / w;
    const double footprint =
        std::max({std::abs(p.s_times_w[0] - s * p.inverse_depth[0]), std::abs(p.s_times_w[1] - s * p.inverse_depth[1]),
                  std::abs(p.t_times_w[0] - t * p.inverse_depth[0]), std::abs(p.t_times_w[1] - t * p.inverse_depth[1])}) /
        w;
    return p.brightness * (1.0 + p.contrast * TextureFade(footprint) * textures_.Sample(p.pattern, s, t));
  };
  radiance->create(height, width, CV_32FC1);
  for (int y = 0; y < height; ++y) {
    const int* id_row = ids.ptr<int>(y);
    float* out = radiance->ptr<float>(y);
    for (int x = 0; x < width;) {
      const int id = id_row[x];
      int end = x + 1;
      while (end < width && id_row[end] == id) ++end;
      if (id < 0) {
        std::fill(out + x, out + end, 0.0f);
      } else if (polygons[id].contrast == 0.0) {
        std::fill(out + x, out + end, static_cast<float>(polygons[id].brightness));
      } else {
        // Along a run of one surface, 1/z and the texture coordinates times 1/z step linearly.
        const Projected& p = polygons[id];
        double w = p.InverseDepth(x, y);
        double sw = p.s_times_w[0] * x + p.s_times_w[1] * y + p.s_times_w[2];
        double tw = p.t_times_w[0] * x + p.t_times_w[1] * y + p.t_times_w[2];
        for (int i = x; i < end; ++i) {
          const double inv = 1.0 / w, s = sw * inv, t = tw * inv;
          // The texture's footprint: scale units per pixel (derivatives of s = S / w and t).
          const double footprint = std::max({std::abs(p.s_times_w[0] - s * p.inverse_depth[0]),
                                             std::abs(p.s_times_w[1] - s * p.inverse_depth[1]),
                                             std::abs(p.t_times_w[0] - t * p.inverse_depth[0]),
                                             std::abs(p.t_times_w[1] - t * p.inverse_depth[1])}) * inv;
          out[i] = static_cast<float>(p.brightness * (1.0 + p.contrast * TextureFade(footprint) *
                                                               textures_.Sample(p.pattern, s, t)));
          w += p.inverse_depth[0];
          sw += p.s_times_w[0];
          tw += p.t_times_w[0];
        }
      }
      x = end;
    }
  }

  // 4. Anti-aliasing where the 3x3 neighbourhood sees more than one surface: first mark both
  // pixels of every 8-connected pair that differ.
  mixed_mask.assign(static_cast<std::size_t>(width) * height, 0);
  for (int y = 0; y < height; ++y) {
    const int* row = ids.ptr<int>(y);
    const int* below = y + 1 < height ? ids.ptr<int>(y + 1) : nullptr;
    unsigned char* mark = mixed_mask.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) {
      const int id = row[x];
      if (x + 1 < width && row[x + 1] != id) mark[x] = mark[x + 1] = 1;
      if (below == nullptr) continue;
      unsigned char* mark_below = mark + width;
      if (below[x] != id) mark[x] = mark_below[x] = 1;
      if (x + 1 < width && below[x + 1] != id) mark[x] = mark_below[x + 1] = 1;
      if (x > 0 && below[x - 1] != id) mark[x] = mark_below[x - 1] = 1;
    }
  }
  std::array<int, 9> candidates;
  std::array<double, 9> coverage;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (!mixed_mask[static_cast<std::size_t>(y) * width + x]) continue;
      const int own = ids.at<int>(y, x);
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, height - 1);
        const int* id_row = ids.ptr<int>(yy);
        for (int dx = -1; dx <= 1; ++dx) {
          const int id = id_row[std::clamp(x + dx, 0, width - 1)];
          if (id == own) continue;
          if (id >= 0 && std::find(candidates.begin(), candidates.begin() + count, id) == candidates.begin() + count) {
            candidates[count++] = id;
          }
        }
      }
      if (own >= 0) candidates[count++] = own;
      // Classify: misses the square, covers it, or is crossed by `crossings` of its edges.
      int full = -1;  // the nearest polygon covering the whole square
      double full_w = -std::numeric_limits<double>::infinity();
      std::array<int, 9> partial;
      std::array<int, 9> crossing_edge;
      int partial_count = 0;
      bool complex = false;
      for (int c = 0; c < count; ++c) {
        const Projected& p = polygons[candidates[c]];
        int crossings = 0, edge = -1;
        bool outside = false;
        for (int i = 0; i < p.vertex_count && !outside; ++i) {
          const Eigen::Vector3d& e = p.edges[i];
          const double d = e[0] * x + e[1] * y + e[2], half = 0.5 * (std::abs(e[0]) + std::abs(e[1]));
          if (d >= half) {
            outside = true;
          } else if (d > -half) {
            ++crossings;
            edge = i;
          }
        }
        if (outside) continue;
        if (crossings == 0) {
          const double w = p.InverseDepth(x, y);
          if (w > full_w) {
            full_w = w;
            full = candidates[c];
          }
        } else if (crossings == 1) {
          partial[partial_count] = candidates[c];
          crossing_edge[partial_count++] = edge;
        } else {
          complex = true;
          partial[partial_count] = candidates[c];
          crossing_edge[partial_count++] = -1;
        }
      }
      // Partial polygons behind the full one at the middle of their part of the square are hidden.
      Clip clip;
      std::array<double, 9> area;
      int kept = 0;
      for (int c = 0; c < partial_count; ++c) {
        const Projected& p = polygons[partial[c]];
        Eigen::Vector2d centroid(x, y);
        clip.Square(x, y);
        if (crossing_edge[c] >= 0) {
          clip.Cut(p.edges[crossing_edge[c]]);
        } else {
          for (int i = 0; i < p.vertex_count; ++i) clip.Cut(p.edges[i]);
        }
        const double a = clip.Area(&centroid);
        if (a <= 0.0) continue;
        if (full >= 0 && polygons[full].InverseDepth(centroid.x(), centroid.y()) >= p.InverseDepth(centroid.x(), centroid.y())) {
          continue;
        }
        partial[kept] = partial[c];
        crossing_edge[kept] = crossing_edge[c];
        area[kept++] = a;
      }
      partial_count = kept;
      double value = 0.0;
      if (partial_count == 0) {
        if (full < 0) continue;
        value = colour(polygons[full], x, y);
      } else if (!complex && partial_count == 1 && full >= 0) {
        value = area[0] * colour(polygons[partial[0]], x, y) + (1.0 - area[0]) * colour(polygons[full], x, y);
      } else if (!complex && partial_count == 2 && full < 0 &&
                 (polygons[partial[0]].edges[crossing_edge[0]] + polygons[partial[1]].edges[crossing_edge[1]]).norm() < 1e-6) {
        // Two polygons sharing the boundary that crosses the pixel.
        value = area[0] * colour(polygons[partial[0]], x, y) + (1.0 - area[0]) * colour(polygons[partial[1]], x, y);
      } else {
        // Supersampling: at each sample the nearest polygon containing it.
        int all[10];
        int n_all = 0;
        for (int c = 0; c < partial_count; ++c) all[n_all++] = partial[c];
        if (full >= 0) all[n_all++] = full;
        std::fill(coverage.begin(), coverage.end(), 0.0);
        int missed = 0;
        for (int sy = 0; sy < kSupersample; ++sy) {
          const double v = y - 0.5 + (sy + 0.5) / kSupersample;
          for (int sx = 0; sx < kSupersample; ++sx) {
            const double u = x - 0.5 + (sx + 0.5) / kSupersample;
            int best = -1;
            double best_w = -std::numeric_limits<double>::infinity();
            for (int c = 0; c < n_all; ++c) {
              const Projected& p = polygons[all[c]];
              if (!p.Contains(u, v)) continue;
              const double w = p.InverseDepth(u, v);
              if (w > best_w) {
                best_w = w;
                best = c;
              }
            }
            if (best >= 0) {
              coverage[best] += 1.0;
            } else {
              ++missed;
            }
          }
        }
        const double total = kSupersample * kSupersample - missed;
        if (total <= 0.0) continue;
        for (int c = 0; c < n_all; ++c) {
          if (coverage[c] > 0.0) value += coverage[c] / total * colour(polygons[all[c]], x, y);
        }
      }
      radiance->at<float>(y, x) = static_cast<float>(value);
    }
  }

  if (surface_ids != nullptr) {
    surface_ids->create(height, width, CV_32SC1);
    for (int y = 0; y < height; ++y) {
      const int* in = ids.ptr<int>(y);
      int* out = surface_ids->ptr<int>(y);
      for (int x = 0; x < width; ++x) out[x] = in[x] < 0 ? -1 : polygons[in[x]].surface;
    }
  }
}

}  // namespace slt
