#include "simulator/scene.h"

#include <algorithm>
#include <utility>

#include "simulator/paper_cuboids.h"
#include "simulator/random_draws.h"

namespace slt {
namespace {

// Up in the world: the camera's y axis points down.
const Eigen::Vector3d kUp(0.0, -1.0, 0.0);

// A vertical wall as seen from inside: (a, b, out) are the distance along the wall from its
// left end, the height above the floor and the distance out of the wall into the room.
struct Wall {
  Eigen::Vector3d origin;  // the left end, on the floor
  Eigen::Vector3d along;   // unit, horizontal, to the right as seen from inside
  Eigen::Vector3d inward;  // unit normal into the room
  Eigen::Vector3d At(double a, double b, double out = 0.0) const {
    return origin + a * along + b * kUp + out * inward;
  }
};

class SceneBuilder {
 public:
  explicit SceneBuilder(std::vector<Line3d>* lines) : lines_(lines) {}
  void Add(const Eigen::Vector3d& p, const Eigen::Vector3d& q) { lines_->push_back({p, q}); }
  void Add(const Wall& w, double a0, double b0, double a1, double b1, double out = 0.0) {
    Add(w.At(a0, b0, out), w.At(a1, b1, out));
  }
  // The four edges of the rectangle [a0, a1] x [b0, b1] on a wall.
  void AddRectangle(const Wall& w, double a0, double b0, double a1, double b1, double out = 0.0) {
    Add(w, a0, b0, a1, b0, out);
    Add(w, a1, b0, a1, b1, out);
    Add(w, a1, b1, a0, b1, out);
    Add(w, a0, b1, a0, b0, out);
  }
  // A horizontal rectangle at height y (a floor or ceiling fixture), x in [x0, x1], z in [z0, z1].
  void AddHorizontalRectangle(double y, double x0, double x1, double z0, double z1) {
    Add({x0, y, z0}, {x1, y, z0});
    Add({x1, y, z0}, {x1, y, z1});
    Add({x1, y, z1}, {x0, y, z1});
    Add({x0, y, z1}, {x0, y, z0});
  }
  // A framed picture: the outer and inner edges of its frame, 2 cm off the wall.
  void AddPicture(const Wall& w, double a0, double b0, double a1, double b1, double frame_width) {
    AddRectangle(w, a0, b0, a1, b1, 0.02);
    AddRectangle(w, a0 + frame_width, b0 + frame_width, a1 - frame_width, b1 - frame_width, 0.02);
  }
  // A door: the jambs and head of its frame, and the edges of the leaf, set into the wall.
  void AddDoor(const Wall& w, double a0, double width, double height) {
    const double a1 = a0 + width;
    Add(w, a0, 0.0, a0, height);
    Add(w, a0, height, a1, height);
    Add(w, a1, height, a1, 0.0);
    const double inset = 0.06;
    Add(w, a0 + inset, 0.0, a0 + inset, height - inset, -0.03);
    Add(w, a0 + inset, height - inset, a1 - inset, height - inset, -0.03);
    Add(w, a1 - inset, height - inset, a1 - inset, 0.0, -0.03);
  }

 private:
  std::vector<Line3d>* lines_;
};

void MakePaperScene(const PaperSceneConfig& c, RandomStream& rng, std::vector<Line3d>* lines) {
  // Always six draws per line: line i uses draws 6i .. 6i+5, so the first N lines of a scene
  // are the N-line scene of the same seed. Cuboid edges (paper_cuboids.h) take the place of the
  // last random lines.
  for (int i = 0; i < c.lines - PaperCuboidLineCount(c); ++i) {
    Eigen::Vector3d mid;
    for (int k = 0; k < 3; ++k) mid[k] = c.box_center_m[k] + c.box_size_m[k] * Uniform(rng, -0.5, 0.5);
    const Eigen::Vector3d direction = UniformUnitVector(rng);
    const double half_length = 0.5 * Uniform(rng, c.min_length_m, c.max_length_m);
    lines->push_back({mid - half_length * direction, mid + half_length * direction});
  }
}

// Books on one shelf board between a0 and a1: one group of 4-9 books standing at a random
// place, spines `out` from the wall. Each book contributes its top edge; between two books
// one vertical edge up to the taller one's top (that is the edge an image shows).
void AddBooks(SceneBuilder& s, const Wall& w, RandomStream& rng, double a0, double a1, double board,
              double max_height, double out) {
  const int count = 4 + static_cast<int>(UniformIndex(rng, 6));
  std::vector<std::pair<double, double>> books;  // (width, height)
  double total = 0.0;
  for (int i = 0; i < count; ++i) {
    books.emplace_back(Uniform(rng, 0.025, 0.06), Uniform(rng, 0.6, 1.0) * max_height);
    total += books.back().first;
  }
  // The caller's shelves are far wider than nine books, so the whole group always fits.
  double a = a0 + Uniform(rng, 0.0, a1 - a0 - total);
  double previous_height = 0.0;
  for (const auto& [width, height] : books) {
    s.Add(w, a, board, a, board + std::max(height, previous_height), out);
    s.Add(w, a, board + height, a + width, board + height, out);
    a += width;
    previous_height = height;
  }
  s.Add(w, a, board, a, board + previous_height, out);
}

void MakeRoomScene(const RoomSceneConfig& c, RandomStream& rng, std::vector<Line3d>* lines) {
  SceneBuilder s(lines);
  const double floor_y = c.camera_height_m, h = c.height_m, W = c.width_m, D = c.depth_m;
  const double z_back = -0.4 * D, z_front = 0.6 * D, x_left = -0.5 * W, x_right = 0.5 * W;
  const Wall front{{x_left, floor_y, z_front}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}};
  const Wall right{{x_right, floor_y, z_front}, {0.0, 0.0, -1.0}, {-1.0, 0.0, 0.0}};
  const Wall back{{x_right, floor_y, z_back}, {-1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};
  const Wall left{{x_left, floor_y, z_back}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}};

  // The shell: vertical corners, floor and ceiling edges, a ceiling lamp.
  for (const Wall* w : {&front, &right, &back, &left}) {
    const double length = (w == &front || w == &back) ? W : D;
    s.Add(*w, 0.0, 0.0, 0.0, h);
    s.Add(*w, 0.0, 0.0, length, 0.0);
    s.Add(*w, 0.0, h, length, h);
  }
  s.AddHorizontalRectangle(floor_y - h, -0.3, 0.3, 0.2 * D - 0.3, 0.2 * D + 0.3);

  // Front wall, left part: a bookshelf 1.6 m wide, 2 m high, 0.32 m deep, six boards.
  const double shelf_a0 = 0.3, shelf_a1 = 1.9, shelf_top = 2.0, shelf_depth = 0.32;
  s.Add(front, shelf_a0, 0.0, shelf_a0, shelf_top, shelf_depth);
  s.Add(front, shelf_a1, 0.0, shelf_a1, shelf_top, shelf_depth);
  s.Add(front.At(shelf_a0, shelf_top, 0.0), front.At(shelf_a0, shelf_top, shelf_depth));
  s.Add(front.At(shelf_a1, shelf_top, 0.0), front.At(shelf_a1, shelf_top, shelf_depth));
  s.Add(front, shelf_a0, shelf_top, shelf_a1, shelf_top, shelf_depth);
  const double board_step = 0.37;
  for (int i = 0; i < 5; ++i) {
    const double board = 0.08 + i * board_step;
    s.Add(front, shelf_a0, board, shelf_a1, board, shelf_depth);
    AddBooks(s, front, rng, shelf_a0 + 0.02, shelf_a1 - 0.02, board, board_step - 0.06, shelf_depth - 0.02);
  }
  // Front wall, middle: a picture above a desk with a monitor; right part: a door.
  const double mid = 0.5 * W;
  const double picture_width = Uniform(rng, 0.6, 0.8), picture_height = Uniform(rng, 0.45, 0.6);
  s.AddPicture(front, mid - 0.3, 1.35, mid - 0.3 + picture_width, 1.35 + picture_height, 0.06);
  const double desk_a0 = mid - 0.1, desk_a1 = mid + 0.9, desk_top = 0.75, desk_out0 = 0.05, desk_out1 = 0.8;
  s.Add(front, desk_a0, desk_top, desk_a1, desk_top, desk_out1);
  s.Add(front, desk_a0, desk_top - 0.03, desk_a1, desk_top - 0.03, desk_out1);
  s.Add(front, desk_a0, desk_top, desk_a1, desk_top, desk_out0);
  s.Add(front.At(desk_a0, desk_top, desk_out0), front.At(desk_a0, desk_top, desk_out1));
  s.Add(front.At(desk_a1, desk_top, desk_out0), front.At(desk_a1, desk_top, desk_out1));
  s.Add(front, desk_a0 + 0.03, 0.0, desk_a0 + 0.03, desk_top - 0.03, desk_out1 - 0.03);
  s.Add(front, desk_a1 - 0.03, 0.0, desk_a1 - 0.03, desk_top - 0.03, desk_out1 - 0.03);
  const double monitor_a0 = mid + 0.2, monitor_out = 0.3;
  s.AddRectangle(front, monitor_a0, 1.0, monitor_a0 + 0.55, 1.33, monitor_out);
  s.AddRectangle(front, monitor_a0 + 0.02, 1.02, monitor_a0 + 0.53, 1.31, monitor_out + 0.005);
  s.Add(front, monitor_a0 + 0.25, desk_top, monitor_a0 + 0.25, 1.0, monitor_out + 0.02);
  s.Add(front, monitor_a0 + 0.30, desk_top, monitor_a0 + 0.30, 1.0, monitor_out + 0.02);
  s.AddDoor(front, W - 1.3, 0.9, 2.05);

  // Left wall: a window with a cross bar and a radiator below it.
  const double window_a0 = 0.55 * D, window_a1 = window_a0 + 1.4;
  s.AddRectangle(left, window_a0, 0.9, window_a1, 2.1);
  s.AddRectangle(left, window_a0 + 0.05, 0.95, window_a1 - 0.05, 2.05, -0.05);
  s.Add(left, 0.5 * (window_a0 + window_a1), 0.95, 0.5 * (window_a0 + window_a1), 2.05, -0.04);
  s.Add(left, window_a0 + 0.05, 1.6, window_a1 - 0.05, 1.6, -0.04);
  s.AddRectangle(left, window_a0 + 0.1, 0.15, window_a1 - 0.1, 0.65, 0.08);
  for (int i = 1; i < 4; ++i) {
    const double a = window_a0 + 0.1 + i * (window_a1 - window_a0 - 0.2) / 4.0;
    s.Add(left, a, 0.15, a, 0.65, 0.08);
  }
  // Right wall: two pictures. Back wall: a door and a poster.
  s.AddPicture(right, 1.0, 1.3, 1.0 + Uniform(rng, 0.5, 0.8), 1.9, 0.05);
  s.AddPicture(right, 2.3, 1.2, 2.3 + Uniform(rng, 0.7, 1.0), 1.8, 0.07);
  s.AddDoor(back, 0.6, 0.9, 2.05);
  s.AddRectangle(back, mid, 1.1, mid + 0.6, 1.9, 0.005);
}

void MakeCorridorScene(const CorridorSceneConfig& c, RandomStream& rng, std::vector<Line3d>* lines) {
  SceneBuilder s(lines);
  const double floor_y = c.camera_height_m, h = c.height_m, W = c.width_m;
  const double z_back = -2.0, z_far = c.length_m - 2.0, x_left = -0.5 * W, x_right = 0.5 * W;
  const double ceiling_y = floor_y - h, length = z_far - z_back;
  // Both side walls are parametrised from the back end along +z (their contents are symmetric,
  // so which end counts as "left" does not matter); `inward` still points into the corridor.
  const Wall left{{x_left, floor_y, z_back}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}};
  const Wall right{{x_right, floor_y, z_back}, {0.0, 0.0, 1.0}, {-1.0, 0.0, 0.0}};
  const Wall far_end{{x_left, floor_y, z_far}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}};
  const Wall back_end{{x_right, floor_y, z_back}, {-1.0, 0.0, 0.0}, {0.0, 0.0, 1.0}};

  // Floor and ceiling edges along the corridor; seams across the floor every 2 m.
  for (const Wall* w : {&left, &right}) {
    s.Add(*w, 0.0, 0.0, length, 0.0);
    s.Add(*w, 0.0, h, length, h);
  }
  for (double z = z_back + 2.0; z < z_far; z += 2.0) s.Add({x_left, floor_y, z}, {x_right, floor_y, z});
  // Ceiling lamps, 0.3 m x 1.2 m, every 3 m.
  for (double z = z_back + 3.5; z + 0.6 < z_far; z += 3.0) {
    s.AddHorizontalRectangle(ceiling_y, -0.15, 0.15, z - 0.6, z + 0.6);
  }
  // Doors, alternately left and right, about every 4 m from about 3 m ahead of the camera; the
  // chair rail (1 m high) and the panel seams below it run between them.
  const double door_width = 0.9, door_height = 2.05, rail = 1.0, panel = 1.2;
  std::vector<double> doors[2];  // start of each door along the wall, per side
  int side = 0;
  for (double a = 5.0 + Uniform(rng, -0.5, 0.5); a + door_width < length - 1.0;
       a += 4.0 + Uniform(rng, -0.5, 0.5), side = 1 - side) {
    doors[side].push_back(a);
  }
  for (int k = 0; k < 2; ++k) {
    const Wall& w = k == 0 ? left : right;
    double start = 0.0;
    doors[k].push_back(length);  // the far end closes the last stretch of wall
    for (const double door : doors[k]) {
      if (door - start > 0.2) s.Add(w, start, rail, door, rail, 0.02);
      for (double a = start + panel; a < door - 0.2; a += panel) s.Add(w, a, 0.1, a, rail, 0.01);
      if (door < length) s.AddDoor(w, door, door_width, door_height);
      start = door + door_width;
    }
  }
  // The end walls: a door at the back, a door and a window at the far end.
  s.AddDoor(back_end, 0.5 * W - 0.45, door_width, door_height);
  s.AddDoor(far_end, 0.5 * W - 0.45, door_width, door_height);
  s.AddRectangle(far_end, 0.5 * W - 0.4, door_height + 0.1, 0.5 * W + 0.4, std::min(h - 0.05, door_height + 0.4));
}

}  // namespace

std::vector<Line3d> MakeScene(const SceneConfig& config, std::uint64_t seed) {
  RandomStream rng = MakeStream(seed, "scene");
  std::vector<Line3d> lines;
  switch (config.type) {
    case SceneType::kPaper:
      AddPaperCuboids(config.paper, seed, &lines);  // ids 0 .. cuboid lines - 1, none by default
      MakePaperScene(config.paper, rng, &lines);
      return lines;
    case SceneType::kRoom: MakeRoomScene(config.room, rng, &lines); break;
    case SceneType::kCorridor: MakeCorridorScene(config.corridor, rng, &lines); break;
  }
  // Fisher-Yates with our own index draw (std::shuffle's output is implementation-defined).
  for (std::size_t i = lines.size(); i > 1; --i) std::swap(lines[i - 1], lines[UniformIndex(rng, i)]);
  return lines;
}

}  // namespace slt
