#include "simulator/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "simulator/paper_cuboids.h"
#include "simulator/random_draws.h"

namespace slt {
namespace {

// Up in the world: the camera's y axis points down.
const Eigen::Vector3d kUp(0.0, -1.0, 0.0);
constexpr std::uint32_t kAllEdges = ~0u;

// A frame on a vertical wall as seen from inside: (a, b, out) are the distance along the wall
// from its left end, the height above the floor and the distance out of the wall into the
// room. With along = x and inward = z it is the floor's frame (a = x, b = height, out = z).
struct Wall {
  Eigen::Vector3d origin;  // the left end, on the floor
  Eigen::Vector3d along;   // unit, horizontal, to the right as seen from inside
  Eigen::Vector3d inward;  // unit normal into the room
  Eigen::Vector3d At(double a, double b, double out = 0.0) const {
    return origin + a * along + b * kUp + out * inward;
  }
};

// Texture presets: the contrasts are kept well below the steps between surfaces, so that the
// edges of the scene are its strongest gradients.
SurfaceTexture Paint(double albedo) { return {albedo, 0.05, TexturePattern::kMottled, 0.4, 0}; }
SurfaceTexture Wood(double albedo) { return {albedo, 0.1, TexturePattern::kGrain, 0.05, 0}; }
SurfaceTexture Cardboard(double albedo) { return {albedo, 0.08, TexturePattern::kMottled, 0.03, 0}; }
SurfaceTexture Flat(double albedo) { return {albedo, 0.0, TexturePattern::kFlat, 0.1, 0}; }
// Lamps shine: an albedo above 1 stands for their own light (kept below saturation, which
// would move their edges).
constexpr double kLampAlbedo = 1.05;

class SceneBuilder {
 public:
  SceneBuilder(std::vector<Surface>* surfaces, std::uint64_t seed)
      : surfaces_(surfaces), texture_key_(StreamSeed(seed, "texture")) {}

  // A convex polygon with the texture frame (origin, s, t); each surface gets its own piece
  // of the pattern unless it continues another one (same frame and seed: pieces of a wall).
  void Add(std::vector<Eigen::Vector3d> vertices, const Eigen::Vector3d& front, SurfaceTexture texture,
           std::uint32_t line_edges, const Eigen::Vector3d& origin, const Eigen::Vector3d& s,
           const Eigen::Vector3d& t, bool own_pattern = true) {
    if (own_pattern) texture.seed = MixSeed(texture_key_ + surfaces_->size());
    Surface surface = MakeSurface(std::move(vertices), front, texture, line_edges);
    surface.texture_origin = origin;
    surface.axis_s = s;
    surface.axis_t = t;
    surfaces_->push_back(std::move(surface));
  }

  // The rectangle [a0, a1] x [b0, b1] on a wall at distance `out`, facing into the room.
  // Edge order: bottom, right, top, left. With `wall_seed` set the pattern continues the
  // wall's own (the pieces of one wall).
  void Rect(const Wall& w, double a0, double b0, double a1, double b1, double out, const SurfaceTexture& texture,
            std::uint32_t edges = kAllEdges, const std::uint64_t* wall_seed = nullptr) {
    SurfaceTexture t = texture;
    if (wall_seed != nullptr) t.seed = *wall_seed;
    Add({w.At(a0, b0, out), w.At(a1, b0, out), w.At(a1, b1, out), w.At(a0, b1, out)}, w.inward, t, edges,
        w.At(0.0, 0.0, out), w.along, kUp, wall_seed == nullptr);
  }

  // The box [a0, a1] x [b0, b1] x [out0, out1] in a wall's frame; every face but those in
  // `skip` ("back" = against the wall, "bottom" = on the floor or a board).
  void Box(const Wall& w, double a0, double b0, double a1, double b1, double out0, double out1,
           const SurfaceTexture& texture, bool skip_back = false, bool skip_bottom = false,
           bool skip_front = false) {
    const auto at = [&](double a, double b, double o) { return w.At(a, b, o); };
    const Eigen::Vector3d corner = at(a0, b0, out0);
    if (!skip_front) {
      Add({at(a0, b0, out1), at(a1, b0, out1), at(a1, b1, out1), at(a0, b1, out1)}, w.inward, texture, kAllEdges,
          corner, w.along, kUp);
    }
    if (!skip_back) {
      Add({at(a0, b0, out0), at(a1, b0, out0), at(a1, b1, out0), at(a0, b1, out0)}, -w.inward, texture, kAllEdges,
          corner, w.along, kUp);
    }
    Add({at(a0, b0, out0), at(a0, b0, out1), at(a0, b1, out1), at(a0, b1, out0)}, -w.along, texture, kAllEdges,
        corner, w.inward, kUp);
    Add({at(a1, b0, out0), at(a1, b0, out1), at(a1, b1, out1), at(a1, b1, out0)}, w.along, texture, kAllEdges,
        corner, w.inward, kUp);
    Add({at(a0, b1, out0), at(a1, b1, out0), at(a1, b1, out1), at(a0, b1, out1)}, kUp, texture, kAllEdges, corner,
        w.along, w.inward);
    if (!skip_bottom) {
      Add({at(a0, b0, out0), at(a1, b0, out0), at(a1, b0, out1), at(a0, b0, out1)}, -kUp, texture, kAllEdges,
          corner, w.along, w.inward);
    }
  }

  // The wall [0, length] x [0, height] minus rectangular openings {a0, b0, a1, b1} (filled by
  // frames, doors, panels added separately), as rectangles: columns between the openings'
  // sides, each split around the openings spanning it. Only the wall's outline is a line;
  // the pieces share the wall's pattern, so the cuts do not show.
  void WallWithOpenings(const Wall& w, double length, double height, const std::vector<Eigen::Vector4d>& openings,
                        const SurfaceTexture& texture) {
    const std::uint64_t seed = MixSeed(texture_key_ + surfaces_->size());
    std::vector<double> columns{0.0, length};
    for (const Eigen::Vector4d& o : openings) columns.insert(columns.end(), {o[0], o[2]});
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    for (std::size_t i = 0; i + 1 < columns.size(); ++i) {
      const double a0 = columns[i], a1 = columns[i + 1];
      std::vector<std::pair<double, double>> blocked;
      for (const Eigen::Vector4d& o : openings) {
        if (o[0] <= a0 && o[2] >= a1) blocked.emplace_back(o[1], o[3]);
      }
      std::sort(blocked.begin(), blocked.end());
      double b = 0.0;
      blocked.emplace_back(height, height);
      for (const auto& [b0, b1] : blocked) {
        if (b0 > b) {
          // Edges: bottom, right, top, left; flagged where they lie on the wall's outline.
          const std::uint32_t edges = (b == 0.0 ? 1u : 0u) | (a1 == length ? 2u : 0u) | (b0 == height ? 4u : 0u) |
                                      (a0 == 0.0 ? 8u : 0u);
          Rect(w, a0, b, a1, b0, 0.0, texture, edges, &seed);
        }
        b = std::max(b, b1);
      }
    }
  }

  // A framed opening [a0, a1] x [b0, b1] in a wall (filling the same opening of the wall): a
  // band of mitred frame pieces `frame_width` wide in the wall's plane (none at the bottom
  // when b0 is the floor), reveals back to depth `recess`, and the leaf or pane there.
  void FramedOpening(const Wall& w, double a0, double b0, double a1, double b1, double frame_width, double recess,
                     const SurfaceTexture& frame, const SurfaceTexture& leaf) {
    const bool bottom_frame = b0 > 0.0;
    const double fw = frame_width, ib0 = bottom_frame ? b0 + fw : b0;
    const double ia0 = a0 + fw, ia1 = a1 - fw, ib1 = b1 - fw;  // the inner opening
    const auto at = [&](double a, double b, double o = 0.0) { return w.At(a, b, o); };
    const Eigen::Vector3d origin = at(0.0, 0.0);
    // Left jamb, head, right jamb, sill piece; edges in the order given, the mitres unflagged.
    Add({at(a0, b0), at(ia0, ib0), at(ia0, ib1), at(a0, b1)}, w.inward, frame, bottom_frame ? 0b1010u : 0b1011u,
        origin, kUp, w.along);
    Add({at(a0, b1), at(ia0, ib1), at(ia1, ib1), at(a1, b1)}, w.inward, frame, 0b1010u, origin, w.along, kUp);
    Add({at(a1, b1), at(ia1, ib1), at(ia1, ib0), at(a1, b0)}, w.inward, frame, bottom_frame ? 0b1010u : 0b1110u,
        origin, kUp, w.along);
    if (bottom_frame) {
      Add({at(a1, b0), at(ia1, ib0), at(ia0, ib0), at(a0, b0)}, w.inward, frame, 0b1010u, origin, w.along, kUp);
    }
    // Reveals: left, top, right.
    const double r = -recess;
    Rect(Wall{at(ia0, 0.0), w.inward * -1.0, w.along}, 0.0, ib0, recess, ib1, 0.0, frame);
    Add({at(ia0, ib1), at(ia1, ib1), at(ia1, ib1, r), at(ia0, ib1, r)}, -kUp, frame, kAllEdges, origin, w.along,
        w.inward);
    Rect(Wall{at(ia1, 0.0, r), w.inward, -w.along}, 0.0, ib0, recess, ib1, 0.0, frame);
    // The sill of a window, the threshold of a door (which closes the floor under the recess).
    Add({at(ia0, ib0), at(ia1, ib0), at(ia1, ib0, r), at(ia0, ib0, r)}, kUp, frame, kAllEdges, origin, w.along,
        w.inward);
    Rect(w, ia0, ib0, ia1, ib1, r, leaf);
  }

  // A picture: a frame box `depth` deep whose front is a band `frame_width` wide around the
  // canvas (a texture boundary).
  void Picture(const Wall& w, double a0, double b0, double a1, double b1, double frame_width, double depth,
               const SurfaceTexture& frame, const SurfaceTexture& canvas) {
    Box(w, a0, b0, a1, b1, 0.0, depth, frame, true, false, true);
    const double fw = frame_width;
    Rect(w, a0, b0, a1, b0 + fw, depth, frame, 0b1011u);          // bottom band
    Rect(w, a0, b1 - fw, a1, b1, depth, frame, 0b1110u);          // top band
    Rect(w, a0, b0 + fw, a0 + fw, b1 - fw, depth, frame, 0b1010u);  // left band
    Rect(w, a1 - fw, b0 + fw, a1, b1 - fw, depth, frame, 0b1010u);  // right band
    Rect(w, a0 + fw, b0 + fw, a1 - fw, b1 - fw, depth, canvas);
  }

  // A table: a top `thickness` thick and four square legs.
  void Table(const Wall& w, double a0, double a1, double out0, double out1, double height, double thickness,
             double leg, const SurfaceTexture& texture) {
    Box(w, a0, height - thickness, a1, height, out0, out1, texture);
    for (const double a : {a0 + 0.02, a1 - 0.02 - leg}) {
      for (const double o : {out0 + 0.02, out1 - 0.02 - leg}) {
        Box(w, a, 0.0, a + leg, height - thickness, o, o + leg, texture, false, true);
      }
    }
  }

 Surface& Last() { return surfaces_->back(); }

 private:
  std::vector<Surface>* surfaces_;
  std::uint64_t texture_key_;
};

// A reflectance for a new book: uniform in [0.12, 0.85], at least 0.15 away from its
// neighbour's so that the spines are told apart.
double BookAlbedo(RandomStream& rng, double previous) {
  while (true) {
    const double albedo = Uniform(rng, 0.12, 0.85);
    if (std::abs(albedo - previous) >= 0.15) return albedo;
  }
}

void MakePaperScene(const PaperSceneConfig& c, RandomStream& rng, std::uint64_t seed, Scene* scene) {
  // Always six draws per line: line i uses draws 6i .. 6i+5, so the first N lines of a scene
  // are the N-line scene of the same seed. Cuboid edges (paper_cuboids.h), already in
  // scene->lines, take the place of the last random lines.
  for (int i = 0; i < c.lines - PaperCuboidLineCount(c); ++i) {
    Eigen::Vector3d mid;
    for (int k = 0; k < 3; ++k) mid[k] = c.box_center_m[k] + c.box_size_m[k] * Uniform(rng, -0.5, 0.5);
    const Eigen::Vector3d direction = UniformUnitVector(rng);
    const double half_length = 0.5 * Uniform(rng, c.min_length_m, c.max_length_m);
    scene->lines.push_back({mid - half_length * direction, mid + half_length * direction});
  }
  // The image form: each segment is one long edge of a bar 4 mm wide, turned towards the
  // camera at frame 0 (about 7 px at 0.5 m), bright on a darker textured backdrop.
  SceneBuilder s(&scene->surfaces, seed);
  const double bar_width = 0.004;
  for (const Line3d& line : scene->lines) {
    const Eigen::Vector3d along = line.q - line.p, mid = 0.5 * (line.p + line.q);
    Eigen::Vector3d across = along.cross(mid);
    if (across.norm() < 1e-9 * along.norm() * mid.norm()) across = along.cross(Eigen::Vector3d::UnitZ());
    if (across.norm() < 1e-12) across = along.cross(Eigen::Vector3d::UnitX());
    across = bar_width * across.normalized();
    s.Add({line.p, line.q, line.q + across, line.p + across}, -mid, Flat(0.85), 0b0001u, line.p,
          along.normalized(), across.normalized());
    scene->surfaces.back().two_sided = true;
  }
  const double z = c.box_center_m.z() + 0.5 * c.box_size_m.z() + 0.7;
  const Wall backdrop{{-4.0, 3.0, z}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}};
  s.Rect(backdrop, 0.0, 0.0, 8.0, 6.0, 0.0, {0.3, 0.2, TexturePattern::kMottled, 0.04, 0}, 0u);
}

// Books on one shelf board between a0 and a1: one group of 4-9 books of random width, height
// and reflectance standing at a random place, spines `front` from the wall.
void AddBooks(SceneBuilder& s, const Wall& w, RandomStream& rng, double a0, double a1, double board,
              double max_height, double front) {
  const int count = 4 + static_cast<int>(UniformIndex(rng, 6));
  std::vector<std::pair<double, double>> books;  // (width, height)
  double total = 0.0;
  for (int i = 0; i < count; ++i) {
    books.emplace_back(Uniform(rng, 0.025, 0.06), Uniform(rng, 0.6, 1.0) * max_height);
    total += books.back().first;
  }
  // The caller's shelves are far wider than nine books, so the whole group always fits.
  double a = a0 + Uniform(rng, 0.0, a1 - a0 - total);
  double albedo = 0.0;
  for (const auto& [width, height] : books) {
    albedo = BookAlbedo(rng, albedo);
    const double depth = Uniform(rng, 0.16, 0.24);
    s.Box(w, a, board, a + width, board + height, front - depth, front, Paint(albedo), true, true);
    a += width;
  }
}

void MakeRoomScene(const RoomSceneConfig& c, RandomStream& rng, std::uint64_t seed, Scene* scene) {
  SceneBuilder s(&scene->surfaces, seed);
  const double floor_y = c.camera_height_m, h = c.height_m, W = c.width_m, D = c.depth_m;
  const double z_back = -0.4 * D, z_front = 0.6 * D, x_left = -0.5 * W, x_right = 0.5 * W;
  const Wall front{{x_left, floor_y, z_front}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}};
  const Wall right{{x_right, floor_y, z_front}, {0.0, 0.0, -1.0}, {-1.0, 0.0, 0.0}};
  const Wall back{{x_right, floor_y, z_back}, {-1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
  const Wall left{{x_left, floor_y, z_back}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}};
  const Wall floor{{0.0, floor_y, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};  // a = x, b = height, out = z
  const double mid = 0.5 * W;

  // The shell: floor, ceiling, four walls with the door and window openings.
  s.Add({{x_left, floor_y, z_back}, {x_right, floor_y, z_back}, {x_right, floor_y, z_front}, {x_left, floor_y, z_front}},
        kUp, Wood(0.42), kAllEdges, {0.0, floor_y, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
  const double ceiling_y = floor_y - h;
  s.Add({{x_left, ceiling_y, z_back}, {x_right, ceiling_y, z_back}, {x_right, ceiling_y, z_front},
         {x_left, ceiling_y, z_front}},
        -kUp, Paint(0.8), kAllEdges, {0.0, ceiling_y, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
  const double door_a0 = W - 1.3, door_width = 0.9, door_height = 2.05;
  const double window_a0 = 0.55 * D, window_a1 = window_a0 + 1.4;
  s.WallWithOpenings(front, W, h, {{door_a0, 0.0, door_a0 + door_width, door_height}}, Paint(0.72));
  s.WallWithOpenings(right, D, h, {}, Paint(0.66));
  s.WallWithOpenings(back, W, h, {{0.6, 0.0, 1.5, door_height}}, Paint(0.7));
  s.WallWithOpenings(left, D, h, {{window_a0, 0.9, window_a1, 2.1}}, Paint(0.64));

  // Front wall, left part: a bookshelf 1.6 m wide, 2 m high, 0.32 m deep, a plinth and four
  // boards, books on each of the five shelves.
  const double shelf_a0 = 0.3, shelf_a1 = 1.9, shelf_top = 2.0, shelf_depth = 0.32, side = 0.02;
  const SurfaceTexture shelf_wood = Wood(0.55), back_panel = Wood(0.32);
  s.Box(front, shelf_a0, 0.0, shelf_a0 + side, shelf_top, 0.0, shelf_depth, shelf_wood, true, true);
  s.Box(front, shelf_a1 - side, 0.0, shelf_a1, shelf_top, 0.0, shelf_depth, shelf_wood, true, true);
  s.Box(front, shelf_a0 + side, shelf_top - side, shelf_a1 - side, shelf_top, 0.0, shelf_depth, shelf_wood, true,
        true);
  s.Rect(front, shelf_a0 + side, 0.0, shelf_a1 - side, shelf_top - side, 0.005, back_panel);
  const double board_step = 0.37;
  for (int i = 0; i < 5; ++i) {
    const double board = 0.08 + i * board_step;
    s.Box(front, shelf_a0 + side, i == 0 ? 0.0 : board - side, shelf_a1 - side, board, 0.005, shelf_depth, shelf_wood,
          true, true);
    AddBooks(s, front, rng, shelf_a0 + 0.04, shelf_a1 - 0.04, board, board_step - 0.06, shelf_depth - 0.02);
  }

  // Front wall, middle: a picture above a desk with a monitor and a keyboard; right: a door.
  const double picture_width = Uniform(rng, 0.6, 0.8), picture_height = Uniform(rng, 0.45, 0.6);
  s.Picture(front, mid - 0.3, 1.35, mid - 0.3 + picture_width, 1.35 + picture_height, 0.06, 0.02, Wood(0.25),
            Paint(Uniform(rng, 0.45, 0.6)));
  const double desk_a0 = mid - 0.1, desk_a1 = mid + 0.9, desk_top = 0.75;
  s.Table(front, desk_a0, desk_a1, 0.05, 0.8, desk_top, 0.03, 0.04, Wood(0.6));
  const double monitor_a0 = mid + 0.2, monitor_out = 0.3;
  s.Box(front, monitor_a0 + 0.25, desk_top, monitor_a0 + 0.3, 1.0, monitor_out - 0.03, monitor_out - 0.01, Flat(0.15),
        false, true);
  s.Box(front, monitor_a0, 1.0, monitor_a0 + 0.55, 1.33, monitor_out - 0.01, monitor_out, Flat(0.1));
  s.Rect(front, monitor_a0 + 0.02, 1.02, monitor_a0 + 0.53, 1.31, monitor_out + 0.002, Paint(0.35));
  s.Box(front, mid + 0.15, desk_top, mid + 0.6, desk_top + 0.02, 0.45, 0.6, Flat(0.2), false, true);
  s.FramedOpening(front, door_a0, 0.0, door_a0 + door_width, door_height, 0.06, 0.04, Paint(0.9), Wood(0.5));

  // Left wall: a window with a cross bar, a sill and a radiator below it; boxes near the corner.
  s.FramedOpening(left, window_a0, 0.9, window_a1, 2.1, 0.05, 0.1, Paint(0.9), Flat(0.97));
  const double window_mid = 0.5 * (window_a0 + window_a1);
  s.Box(left, window_mid - 0.02, 0.95, window_mid + 0.02, 1.58, -0.1, -0.06, Paint(0.9), true);
  s.Box(left, window_mid - 0.02, 1.62, window_mid + 0.02, 2.05, -0.1, -0.06, Paint(0.9), true);
  s.Box(left, window_a0 + 0.05, 1.58, window_a1 - 0.05, 1.62, -0.1, -0.06, Paint(0.9), true);
  s.Box(left, window_a0 - 0.05, 0.87, window_a1 + 0.05, 0.9, 0.0, 0.12, Paint(0.85), true);
  const double radiator_a0 = window_a0 + 0.1, radiator_a1 = window_a1 - 0.1;
  s.Box(left, radiator_a0, 0.15, radiator_a1, 0.65, 0.04, 0.1, Paint(0.8), true, false, true);
  const int fins = 8;
  for (int i = 0; i < fins; ++i) {
    const double a = radiator_a0 + i * (radiator_a1 - radiator_a0) / fins;
    s.Rect(left, a, 0.15, a + (radiator_a1 - radiator_a0) / fins, 0.65, 0.1, Paint(i % 2 ? 0.8 : 0.62));
  }
  const double box_a = D - 1.0, box_width = Uniform(rng, 0.4, 0.55), box_height = Uniform(rng, 0.3, 0.45);
  s.Box(left, box_a, 0.0, box_a + box_width, box_height, 0.05, 0.05 + Uniform(rng, 0.35, 0.5), Cardboard(0.5),
        false, true);
  s.Box(left, box_a + 0.05, box_height, box_a + 0.05 + Uniform(rng, 0.25, 0.35),
        box_height + Uniform(rng, 0.15, 0.3), 0.1, 0.1 + Uniform(rng, 0.25, 0.32), Cardboard(0.36), false, true);

  // Right wall: two pictures, a low table with a box on it. Back wall: a door and a poster.
  s.Picture(right, 1.0, 1.3, 1.0 + Uniform(rng, 0.5, 0.8), 1.9, 0.05, 0.02, Wood(0.3), Paint(Uniform(rng, 0.4, 0.55)));
  s.Picture(right, 2.3, 1.2, 2.3 + Uniform(rng, 0.7, 1.0), 1.8, 0.07, 0.02, Paint(0.88), Paint(Uniform(rng, 0.2, 0.35)));
  s.Table(right, 0.6, 1.5, 0.1, 0.6, 0.7, 0.03, 0.04, Wood(0.38));
  s.Box(right, 0.8, 0.7, 1.1, 0.7 + Uniform(rng, 0.15, 0.25), 0.2, 0.45, Cardboard(0.58), false, true);
  s.FramedOpening(back, 0.6, 0.0, 1.5, door_height, 0.06, 0.04, Paint(0.9), Wood(0.5));
  s.Rect(back, mid, 1.1, mid + 0.6, 1.9, 0.005, Paint(0.3));
  // A ceiling lamp.
  s.Box(floor, -0.3, h - 0.04, 0.3, h, 0.2 * D - 0.3, 0.2 * D + 0.3, Flat(kLampAlbedo));
}

void MakeCorridorScene(const CorridorSceneConfig& c, RandomStream& rng, std::uint64_t seed, Scene* scene) {
  SceneBuilder s(&scene->surfaces, seed);
  const double floor_y = c.camera_height_m, h = c.height_m, W = c.width_m;
  const double z_back = -2.0, z_far = c.length_m - 2.0, x_left = -0.5 * W, x_right = 0.5 * W;
  const double ceiling_y = floor_y - h, length = z_far - z_back;
  // Both side walls are parametrised from the back end along +z (their contents are symmetric,
  // so which end counts as "left" does not matter); `inward` still points into the corridor.
  const Wall left{{x_left, floor_y, z_back}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}};
  const Wall right{{x_right, floor_y, z_back}, {0.0, 0.0, 1.0}, {-1.0, 0.0, 0.0}};
  const Wall far_end{{x_left, floor_y, z_far}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}};
  const Wall back_end{{x_right, floor_y, z_back}, {-1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
  const Wall floor{{0.0, floor_y, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};

  // Floor slabs 2 m long in two shades (their seams are lines), the ceiling, ceiling lamps
  // 0.3 m x 1.2 m every 3 m.
  for (double z = z_back; z < z_far - 1e-9; z += 2.0) {
    const double z1 = std::min(z + 2.0, z_far);
    const bool dark = static_cast<int>(std::lround((z - z_back) / 2.0)) % 2 == 1;
    s.Add({{x_left, floor_y, z}, {x_right, floor_y, z}, {x_right, floor_y, z1}, {x_left, floor_y, z1}}, kUp,
          Wood(dark ? 0.36 : 0.46), kAllEdges, {0.0, floor_y, 0.0}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0});
  }
  s.Add({{x_left, ceiling_y, z_back}, {x_right, ceiling_y, z_back}, {x_right, ceiling_y, z_far},
         {x_left, ceiling_y, z_far}},
        -kUp, Paint(0.82), kAllEdges, {0.0, ceiling_y, 0.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
  for (double z = z_back + 3.5; z + 0.6 < z_far; z += 3.0) {
    s.Box(floor, -0.15, h - 0.03, 0.15, h, z - 0.6, z + 0.6, Flat(kLampAlbedo));
  }
  // Doors, alternately left and right, about every 4 m from about 3 m ahead of the camera;
  // between them a rail band at 1 m over panels 1.2 m wide in two shades.
  const double door_width = 0.9, door_height = 2.05, rail = 1.0, rail_height = 0.06, panel = 1.2;
  std::vector<double> doors[2];  // start of each door along the wall, per side
  int side = 0;
  for (double a = 5.0 + Uniform(rng, -0.5, 0.5); a + door_width < length - 1.0;
       a += 4.0 + Uniform(rng, -0.5, 0.5), side = 1 - side) {
    doors[side].push_back(a);
  }
  for (int k = 0; k < 2; ++k) {
    const Wall& w = k == 0 ? left : right;
    std::vector<Eigen::Vector4d> openings;
    double start = 0.0;
    doors[k].push_back(length);  // the far end closes the last stretch of wall
    for (const double door : doors[k]) {
      if (door - start > 0.2) {
        openings.emplace_back(start, 0.0, door, rail + rail_height);
        s.Rect(w, start, rail, door, rail + rail_height, 0.0, Paint(0.4), 0b0101u);
        int i = 0;
        for (double a = start; a < door - 1e-9; a += panel, ++i) {
          const double a1 = std::min(a + panel, door);
          s.Rect(w, a, 0.0, a1, rail, 0.0, Paint(i % 2 ? 0.66 : 0.55));
        }
      }
      if (door < length) {
        openings.emplace_back(door, 0.0, door + door_width, door_height);
        s.FramedOpening(w, door, 0.0, door + door_width, door_height, 0.06, 0.04, Paint(0.88), Wood(0.45));
      }
      start = door + door_width;
    }
    s.WallWithOpenings(w, length, h, openings, Paint(0.75));
  }
  // The end walls: a door at the back, a door and a window at the far end.
  const double end_door = 0.5 * W - 0.45, window_top = std::min(h - 0.05, door_height + 0.4);
  s.WallWithOpenings(back_end, W, h, {{end_door, 0.0, end_door + door_width, door_height}}, Paint(0.7));
  s.FramedOpening(back_end, end_door, 0.0, end_door + door_width, door_height, 0.06, 0.04, Paint(0.88), Wood(0.45));
  s.WallWithOpenings(far_end, W, h,
                     {{end_door, 0.0, end_door + door_width, door_height},
                      {0.5 * W - 0.4, door_height + 0.1, 0.5 * W + 0.4, window_top}},
                     Paint(0.7));
  s.FramedOpening(far_end, end_door, 0.0, end_door + door_width, door_height, 0.06, 0.04, Paint(0.88), Wood(0.45));
  s.FramedOpening(far_end, 0.5 * W - 0.4, door_height + 0.1, 0.5 * W + 0.4, window_top, 0.04, 0.08, Paint(0.88),
                  Flat(0.97));
}



// Sizes of the street's cross-section (m), from the centre line: two lanes of 3.5 m, a parking
// lane of 2 m, the curb (0.15 m high), a sidewalk of 3 m, the facades.
constexpr double kLaneWidth = 3.5, kCurbOffset = 5.5, kFacadeOffset = 8.5, kCurbHeight = 0.15;
// The renderer shades a downward-facing surface by about 0.31 (render/rasterizer.h: 0.6 + 0.35
// n.L): the sky's albedo stands for its own light, bright but below saturation.
constexpr double kSkyAlbedo = 2.6;
// No parked car, lamp post or sign within this distance of a crossing's facades (m): the
// corners stay clear for turning cars.
constexpr double kCornerClearance = 15.0;

SurfaceTexture Asphalt() { return {0.2, 0.12, TexturePattern::kMottled, 0.06, 0}; }
SurfaceTexture Plaster(double albedo) { return {albedo, 0.06, TexturePattern::kMottled, 0.3, 0}; }
SurfaceTexture Glass(double albedo) { return {albedo, 0.03, TexturePattern::kMottled, 0.5, 0}; }

// One side of a street between two corners: the facade's wall frame (a along it, b up from
// the sidewalk, out into the street) and its length; clear_start / clear_end: whether the
// start or the end meets a crossing (kept clear of cars and posts).
struct StreetSide {
  Wall wall;
  double length;
  bool clear_start;
  bool clear_end;
};

class StreetBuilder {
 public:
  StreetBuilder(SceneBuilder* s, RandomStream* rng) : s_(*s), rng_(*rng) {}

  // Buildings 8-20 m wide side by side along the facade, 3-6 storeys each.
  void Facade(const StreetSide& side) {
    double a = 0.0, previous_height = 0.0;
    while (a < side.length - 1e-9) {
      double width = Uniform(rng_, 8.0, 20.0);
      if (side.length - (a + width) < 6.0) width = side.length - a;  // no sliver at the end
      const double height = Building(side.wall, a, a + width);
      // The taller of two neighbours shows its side wall above the lower one's roof.
      if (a > 0.0 && previous_height != height) {
        const bool left_taller = previous_height > height;
        SideWall(side.wall, a, std::min(previous_height, height), std::max(previous_height, height), left_taller);
      }
      previous_height = height;
      a += width;
    }
  }

  // Lamp posts every 25 m and a sign every 40 m on the sidewalk, parked cars in the parking
  // lane, none near the corners.
  void StreetFurniture(const StreetSide& side) {
    const Wall& w = side.wall;
    const double lo = side.clear_start ? kCornerClearance : 2.0;
    const double hi = side.length - (side.clear_end ? kCornerClearance : 2.0);
    const double curb = kFacadeOffset - kCurbOffset;  // the curb's distance from the facade
    for (double a = lo + Uniform(rng_, 0.0, 10.0); a < hi; a += 25.0) {
      s_.Box(w, a, 0.0, a + 0.16, 6.5, curb - 0.7, curb - 0.54, Paint(0.3), false, true);
      s_.Box(w, a + 0.03, 6.3, a + 0.13, 6.4, curb - 0.54, curb + 1.2, Paint(0.3), true, false);
      s_.Box(w, a - 0.1, 6.15, a + 0.26, 6.3, curb + 0.8, curb + 1.5, Flat(0.75), false, false);
    }
    for (double a = lo + Uniform(rng_, 0.0, 20.0); a < hi; a += 40.0) {
      s_.Box(w, a, 0.0, a + 0.07, 2.9, curb - 0.45, curb - 0.38, Paint(0.5), false, true);
      s_.Box(w, a + 0.07, 2.1, a + 0.1, 2.8, curb - 0.76, curb - 0.06, Flat(Uniform(rng_, 0.7, 0.95)));
    }
    // The parking lane lies kCurbOffset - kLaneWidth wide beyond the curb, a step below the
    // sidewalk (b = -kCurbHeight is the road).
    for (double a = lo + Uniform(rng_, 0.0, 4.0); a + 4.4 < hi;) {
      if (Uniform01(rng_) < 0.6) {
        const SurfaceTexture paint = Paint(Uniform(rng_, 0.15, 0.85));
        const double b = -kCurbHeight;
        s_.Box(w, a, b + 0.3, a + 4.3, b + 1.0, curb + 0.2, curb + 1.85, paint, false, true);
        s_.Box(w, a + 1.1, b + 1.0, a + 3.3, b + 1.45, curb + 0.32, curb + 1.73, Glass(0.16), false, true);
        a += 4.3 + Uniform(rng_, 0.8, 2.5);
      } else {
        a += Uniform(rng_, 3.0, 9.0);
      }
    }
  }

 private:
  // A building on [a0, a1] of the facade; returns its height.
  double Building(const Wall& w, double a0, double a1) {
    const int storeys = 3 + static_cast<int>(UniformIndex(rng_, 4));
    const double ground = Uniform(rng_, 3.8, 4.4), storey = Uniform(rng_, 3.0, 3.4);
    const double top = ground + (storeys - 1) * storey, height = top + Uniform(rng_, 0.6, 1.2);
    const double width = a1 - a0;
    const SurfaceTexture plaster = Plaster(Uniform(rng_, 0.45, 0.8));
    s_.Rect(w, a0, 0.0, a1, height, 0.0, plaster);
    // A cornice under the roof line and a band between the ground floor and the first floor.
    s_.Box(w, a0, top + 0.1, a1, top + 0.4, 0.0, 0.3, Plaster(Uniform(rng_, 0.55, 0.9)), true);
    s_.Rect(w, a0, ground - 0.3, a1, ground, 0.02, Plaster(Uniform(rng_, 0.35, 0.85)));
    // Windows: a frame with the pane in front of it, in columns over the upper storeys.
    const double pitch = Uniform(rng_, 2.3, 3.2), pane_width = Uniform(rng_, 1.0, 1.4);
    const double pane_height = Uniform(rng_, 1.3, 1.7), frame = Uniform(rng_, 0.08, 0.14);
    const SurfaceTexture frame_paint = Paint(Uniform(rng_, 0.1, 0.95)), glass = Glass(Uniform(rng_, 0.1, 0.22));
    const int columns = std::max(1, static_cast<int>((width - 1.0) / pitch));
    const double margin = 0.5 * (width - columns * pitch);
    for (int floor = 1; floor < storeys; ++floor) {
      const double sill = ground + (floor - 1) * storey + 0.9;
      for (int c = 0; c < columns; ++c) {
        const double mid = a0 + margin + (c + 0.5) * pitch;
        Window(w, mid - 0.5 * pane_width, sill, mid + 0.5 * pane_width, sill + pane_height, frame, frame_paint, glass);
      }
    }
    // The ground floor: a shop front (a wide window, a door, a sign board, maybe an awning)
    // or a house door between windows.
    if (Uniform01(rng_) < 0.6) {
      const double door = a0 + margin + Uniform(rng_, 0.3, 1.0);
      Window(w, door, 0.0, door + 1.1, 2.4, 0.1, frame_paint, Glass(0.14));
      const double shop0 = door + 1.6, shop1 = a1 - margin - 0.3;
      if (shop1 - shop0 > 1.5) Window(w, shop0, 0.5, shop1, 2.8, 0.12, frame_paint, glass);
      s_.Rect(w, a0 + margin, 3.0, a1 - margin, 3.6, 0.06, Paint(Uniform(rng_, 0.1, 0.95)));
      if (Uniform01(rng_) < 0.5 && shop1 - shop0 > 1.5) {
        // An awning sloping down from the wall: lines of an oblique direction.
        s_.Add({w.At(shop0, 2.95, 0.08), w.At(shop1, 2.95, 0.08), w.At(shop1, 2.55, 1.3), w.At(shop0, 2.55, 1.3)},
               w.inward - kUp, Paint(Uniform(rng_, 0.2, 0.8)), kAllEdges, w.At(0.0, 0.0, 0.0), w.along, kUp);
        surface_back().two_sided = true;
      }
    } else {
      const double door = 0.5 * (a0 + a1) - 0.6;
      Window(w, door, 0.0, door + 1.2, 2.5, 0.12, frame_paint, Paint(Uniform(rng_, 0.15, 0.45)));
      for (int c = 0; c < columns; ++c) {
        const double mid = a0 + margin + (c + 0.5) * pitch;
        if (std::abs(mid - (door + 0.6)) < 0.5 * pitch + 0.7) continue;
        Window(w, mid - 0.5 * pane_width, 1.0, mid + 0.5 * pane_width, 1.0 + pane_height, frame, frame_paint, glass);
      }
    }
    return height;
  }

  // A frame of width `frame` around the pane [a0, a1] x [b0, b1] (the pane 1 cm in front).
  void Window(const Wall& w, double a0, double b0, double a1, double b1, double frame, const SurfaceTexture& paint,
              const SurfaceTexture& pane) {
    const double fb0 = b0 > 0.0 ? b0 - frame : b0;  // a door's frame stands on the sidewalk
    s_.Rect(w, a0 - frame, fb0, a1 + frame, b1 + frame, 0.03, paint);
    s_.Rect(w, a0, b0, a1, b1, 0.04, pane);
  }

  // The side wall at a of the taller of two neighbours, above the lower one's roof, 10 m deep,
  // facing the lower one.
  void SideWall(const Wall& w, double a, double b0, double b1, bool left_taller) {
    const Wall side{w.At(a, 0.0), left_taller ? -w.inward : w.inward, left_taller ? w.along : -w.along};
    const double d0 = left_taller ? 0.0 : -10.0, d1 = left_taller ? 10.0 : 0.0;
    s_.Rect(side, d0, b0, d1, b1, 0.0, Plaster(0.5), 0b1110u);
  }

  Surface& surface_back() { return s_.Last(); }

  SceneBuilder& s_;
  RandomStream& rng_;
};

// Lane markings on the road, 2 mm above the asphalt (not in its plane: a coplanar surface would
// tie in the z-buffer): white paint, the rectangle [x0, x1] x [z0, z1] in world x and z.
void RoadPaint(SceneBuilder& s, double road_y, double x0, double z0, double x1, double z1) {
  const double y = road_y - 0.002;
  s.Add({{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, kUp, Flat(0.8), kAllEdges, {0.0, y, 0.0},
        {1.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
}

void MakeStreetScene(const StreetSceneConfig& c, RandomStream& rng, std::uint64_t seed, Scene* scene) {
  SceneBuilder s(&scene->surfaces, seed);
  StreetBuilder street(&s, &rng);
  const double road_y = c.camera_height_m, walk_y = road_y - kCurbHeight;
  const double x0 = -c.lane_offset_m, zc = c.crossing_at_m;  // the two centre lines
  const double z_back = -30.0, z_far = zc + kFacadeOffset + c.far_length_m;
  const double x_lo = x0 - c.cross_length_m, x_hi = x0 + c.cross_length_m;
  const double F = kFacadeOffset, C = kCurbOffset;
  const auto ground = [&](double y, double xa, double za, double xb, double zb, const SurfaceTexture& texture,
                          const std::uint64_t* wall_seed) {
    SurfaceTexture t = texture;
    if (wall_seed != nullptr) t.seed = *wall_seed;
    s.Add({{xa, y, za}, {xb, y, za}, {xb, y, zb}, {xa, y, zb}}, kUp, t, 0u, {0.0, y, 0.0}, {1.0, 0.0, 0.0},
          {0.0, 0.0, 1.0}, wall_seed == nullptr);
  };

  // The road: five pieces of one asphalt (the arms and the crossing), no lines of their own
  // (the curbs and the paint make them).
  const std::uint64_t asphalt_seed = MixSeed(StreamSeed(seed, "asphalt"));
  ground(road_y, x0 - C, z_back, x0 + C, zc - C, Asphalt(), &asphalt_seed);
  ground(road_y, x0 - C, zc - C, x0 + C, zc + C, Asphalt(), &asphalt_seed);
  ground(road_y, x0 - C, zc + C, x0 + C, z_far, Asphalt(), &asphalt_seed);
  ground(road_y, x_lo, zc - C, x0 - C, zc + C, Asphalt(), &asphalt_seed);
  ground(road_y, x0 + C, zc - C, x_hi, zc + C, Asphalt(), &asphalt_seed);

  // The four blocks' sidewalks (an L each: the main street's strip runs to its corner) and the
  // curbs' faces towards the road. sx, sz: the block's side of the main and the cross street.
  for (const double sx : {-1.0, 1.0}) {
    for (const double sz : {-1.0, 1.0}) {
      const double main_z0 = sz < 0 ? z_back : zc + C, main_z1 = sz < 0 ? zc - C : z_far;
      const double cross_x0 = sx < 0 ? x_lo : x0 + F, cross_x1 = sx < 0 ? x0 - F : x_hi;
      const double walk_x0 = std::min(x0 + sx * C, x0 + sx * F), walk_x1 = std::max(x0 + sx * C, x0 + sx * F);
      const double walk_z0 = std::min(zc + sz * C, zc + sz * F), walk_z1 = std::max(zc + sz * C, zc + sz * F);
      ground(walk_y, walk_x0, main_z0, walk_x1, main_z1, Paint(0.52), nullptr);
      ground(walk_y, cross_x0, walk_z0, cross_x1, walk_z1, Paint(0.52), nullptr);
      // The curb faces: vertical, facing the road.
      const double curb_x = x0 + sx * C, curb_z = zc + sz * C;
      const double cx0 = sx < 0 ? x_lo : curb_x, cx1 = sx < 0 ? curb_x : x_hi;
      s.Add({{curb_x, road_y, main_z0}, {curb_x, road_y, main_z1}, {curb_x, walk_y, main_z1}, {curb_x, walk_y, main_z0}},
            {-sx, 0.0, 0.0}, Paint(0.6), kAllEdges, {curb_x, road_y, 0.0}, {0.0, 0.0, 1.0}, kUp);
      s.Add({{cx0, road_y, curb_z}, {cx1, road_y, curb_z}, {cx1, walk_y, curb_z}, {cx0, walk_y, curb_z}},
            {0.0, 0.0, -sz}, Paint(0.6), kAllEdges, {0.0, road_y, curb_z}, {1.0, 0.0, 0.0}, kUp);
    }
  }

  // Where a street ends at a row of facades, a step up from the road to the facades' base.
  for (const double sz : {-1.0, 1.0}) {
    const double z = sz < 0 ? z_back : z_far, x = sz < 0 ? x_lo : x_hi;
    s.Add({{x0 - C, road_y, z}, {x0 + C, road_y, z}, {x0 + C, walk_y, z}, {x0 - C, walk_y, z}}, {0.0, 0.0, -sz},
          Paint(0.6), kAllEdges, {0.0, road_y, z}, {1.0, 0.0, 0.0}, kUp);
    s.Add({{x, road_y, zc - C}, {x, road_y, zc + C}, {x, walk_y, zc + C}, {x, walk_y, zc - C}}, {-sz, 0.0, 0.0},
          Paint(0.6), kAllEdges, {x, road_y, 0.0}, {0.0, 0.0, 1.0}, kUp);
  }

  // Lane markings: dashed centre lines (3 m of every 9 m), the lines between the lanes and the
  // parking lanes, zebra crossings on the four arms.
  for (double z = z_back; z + 3.0 < z_far; z += 9.0) {
    if (z + 3.0 > zc - C - 4.0 && z < zc + C + 4.0) continue;
    RoadPaint(s, road_y, x0 - 0.075, z, x0 + 0.075, z + 3.0);
  }
  for (double x = x0 + C + 5.0; x + 3.0 < x_hi; x += 9.0) RoadPaint(s, road_y, x, zc - 0.075, x + 3.0, zc + 0.075);
  for (double x = x0 - C - 5.0; x - 3.0 > x_lo; x -= 9.0) RoadPaint(s, road_y, x - 3.0, zc - 0.075, x, zc + 0.075);
  for (const double sx : {-1.0, 1.0}) {
    const double x = x0 + sx * kLaneWidth;
    RoadPaint(s, road_y, x - 0.06, z_back, x + 0.06, zc - C - 4.0);
    RoadPaint(s, road_y, x - 0.06, zc + C + 4.0, x + 0.06, z_far);
    const double z = zc + sx * kLaneWidth;
    RoadPaint(s, road_y, x0 + C + 4.0, z - 0.06, x_hi, z + 0.06);
    RoadPaint(s, road_y, x_lo, z - 0.06, x0 - C - 4.0, z + 0.06);
  }
  for (int stripe = 0; stripe < 10; ++stripe) {
    const double u = -C + 0.3 + 1.05 * stripe;  // across the arm
    for (const double side : {-1.0, 1.0}) {
      const double near = side * (C + 0.5), far = side * (C + 3.5);
      RoadPaint(s, road_y, x0 + u, zc + std::min(near, far), x0 + u + 0.5, zc + std::max(near, far));
      RoadPaint(s, road_y, x0 + std::min(near, far), zc + u, x0 + std::max(near, far), zc + u + 0.5);
    }
  }

  // The facades, as seen from the street (along: to the right), with what stands in front.
  const auto wall = [&](double x, double z, const Eigen::Vector3d& along) {
    return Wall{{x, walk_y, z}, along, along.cross(kUp)};
  };
  const Eigen::Vector3d px(1.0, 0.0, 0.0), pz(0.0, 0.0, 1.0);
  const double main_near = zc - F - z_back, main_far = z_far - (zc + F), cross = c.cross_length_m - F;
  const std::vector<StreetSide> sides = {
      {wall(x0 + F, zc - F, -pz), main_near, true, false},  // main street, right, before the crossing
      {wall(x0 - F, z_back, pz), main_near, false, true},   // main street, left, before the crossing
      {wall(x0 + F, z_far, -pz), main_far, false, true},    // main street, right, beyond
      {wall(x0 - F, zc + F, pz), main_far, true, false},    // main street, left, beyond
      {wall(x_hi, zc - F, -px), cross, false, true},        // cross street, near side, right
      {wall(x0 - F, zc - F, -px), cross, true, false},      // cross street, near side, left
      {wall(x0 + F, zc + F, px), cross, true, false},       // cross street, far side, right
      {wall(x_lo, zc + F, px), cross, false, true},         // cross street, far side, left
      {wall(x0 - F, z_far, px), 2.0 * F, false, false},     // the main street's far end
      {wall(x0 + F, z_back, -px), 2.0 * F, false, false},   // its back end
      {wall(x_hi, zc + F, -pz), 2.0 * F, false, false},     // the cross street's ends
      {wall(x_lo, zc - F, pz), 2.0 * F, false, false},
  };
  for (std::size_t i = 0; i < sides.size(); ++i) {
    street.Facade(sides[i]);
    if (i < 8) street.StreetFurniture(sides[i]);
  }

  // Traffic lights at three corners of the crossing (the fourth is the inside of the car
  // profile's right turn), on the sidewalk 2 m from the corner.
  const Wall level{{0.0, walk_y, 0.0}, px, pz};  // a = x, b = up from the sidewalk, out = z
  for (const auto& [sx, sz] : {std::pair{-1.0, -1.0}, std::pair{-1.0, 1.0}, std::pair{1.0, 1.0}}) {
    const double x = x0 + sx * (C + 1.0), z = zc + sz * (C + 1.0);
    s.Box(level, x - 0.08, 0.0, x + 0.08, 3.4, z - 0.08, z + 0.08, Paint(0.25), false, true);
    s.Box(level, x - 0.18, 3.4, x + 0.18, 4.4, z - 0.15, z + 0.15, Flat(0.1));
  }

  // The sky: one plane 200 m above the road, far wider than the streets (its edges lie below
  // the roofs, seen from the road), no lines.
  const double sky_y = road_y - 200.0, reach = 20000.0;
  s.Add({{-reach, sky_y, -reach}, {reach, sky_y, -reach}, {reach, sky_y, reach}, {-reach, sky_y, reach}}, -kUp,
        Flat(kSkyAlbedo), 0u, {0.0, sky_y, 0.0}, px, pz);
}

}  // namespace

Scene MakeScene(const SceneConfig& config, std::uint64_t seed) {
  RandomStream rng = MakeStream(seed, "scene");
  Scene scene;
  switch (config.type) {
    case SceneType::kPaper:
      AddPaperCuboids(config.paper, seed, &scene.lines);  // ids 0 .. cuboid lines - 1, none by default
      MakePaperScene(config.paper, rng, seed, &scene);
      return scene;
    case SceneType::kRoom: MakeRoomScene(config.room, rng, seed, &scene); break;
    case SceneType::kCorridor: MakeCorridorScene(config.corridor, rng, seed, &scene); break;
    case SceneType::kStreet: MakeStreetScene(config.street, rng, seed, &scene); break;
  }
  scene.lines = LinesFromSurfaces(scene.surfaces);
  // Fisher-Yates with our own index draw (std::shuffle's output is implementation-defined).
  std::vector<Line3d>& lines = scene.lines;
  for (std::size_t i = lines.size(); i > 1; --i) std::swap(lines[i - 1], lines[UniformIndex(rng, i)]);
  return scene;
}

}  // namespace slt
