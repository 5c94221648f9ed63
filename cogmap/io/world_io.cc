#include "cogmap/io/world_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/grid_io.h"

namespace cogmap::io {
namespace {

struct Token {
  std::string text;
  bool quoted = false;
};

std::vector<Token> Tokenize(const std::string& s) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i >= s.size()) break;
    Token t;
    if (s[i] == '"') {
      t.quoted = true;
      const size_t end = s.find('"', i + 1);
      t.text = s.substr(i + 1, end == std::string::npos ? std::string::npos : end - i - 1);
      i = end == std::string::npos ? s.size() : end + 1;
    } else {
      const size_t start = i;
      while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
      t.text = s.substr(start, i - start);
    }
    out.push_back(std::move(t));
  }
  return out;
}

// Coordinates (mm) and headings (degrees) beyond this are refused: grids and
// pictures of the world are sized from its extent.
constexpr double kMaxWorldNumber = 1e8;

bool ParseNumber(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(*v);
}

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// wpNN -> NN, or -1.
long RouteNumber(const std::string& name) {
  if (name.size() < 3 || (name[0] != 'w' && name[0] != 'W') || (name[1] != 'p' && name[1] != 'P')) return -1;
  long n = 0;
  for (size_t i = 2; i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return -1;
    n = n * 10 + (name[i] - '0');
    if (n > 1000000000L) return -1;
  }
  return n;
}

}  // namespace

WorldReadResult ParseAriaMap(const std::string& text, const std::string& path) {
  WorldReadResult result;
  FloorPlan& plan = result.plan;
  std::istringstream in(text);
  std::string raw;
  long line_no = 0;
  enum class Section { kHeader, kLines, kData } section = Section::kHeader;
  long data_points = 0;
  bool have_min = false, have_max = false;
  std::multimap<long, std::pair<long, Waypoint>> route;  // number -> (line, waypoint)
  auto numbers = [&](const std::vector<Token>& tok, size_t from, size_t n, const std::string& what) {
    std::vector<double> v(n);
    if (tok.size() < from + n)
      throw InputError(path, line_no, what + ": expected " + std::to_string(n) + " numbers, got " +
                                          std::to_string(tok.size() > from ? tok.size() - from : 0));
    for (size_t i = 0; i < n; ++i) {
      if (tok[from + i].quoted || !ParseNumber(tok[from + i].text, &v[i]))
        throw InputError(path, line_no, what + ": '" + tok[from + i].text + "' is not a number");
      if (std::abs(v[i]) > kMaxWorldNumber)
        throw InputError(path, line_no,
                         what + ": '" + tok[from + i].text + "' is out of range (at most 1e8: 100 km in mm)");
    }
    return v;
  };
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = Trim(raw);
    if (line_no == 1) {
      if (line.rfind("2D-Map", 0) != 0)
        throw InputError(path, 1, "not an ARIA 2D-Map file (the first line must be '2D-Map')");
      continue;
    }
    if (line.empty() || line[0] == ';' || line[0] == '#') continue;
    if (line == "LINES") {
      section = Section::kLines;
      continue;
    }
    if (line == "DATA") {
      section = Section::kData;
      continue;
    }
    const auto tok = Tokenize(line);
    if (section == Section::kLines) {
      if (tok.size() != 4)
        throw InputError(path, line_no, "LINES: expected 4 numbers x1 y1 x2 y2, got " +
                                            std::to_string(tok.size()) + " fields");
      const auto v = numbers(tok, 0, 4, "LINES");
      plan.walls.push_back({{v[0] / 1000.0, v[1] / 1000.0}, {v[2] / 1000.0, v[3] / 1000.0}});
      continue;
    }
    if (section == Section::kData) {
      if (tok.size() != 2) throw InputError(path, line_no, "DATA: expected 2 numbers x y, got " +
                                                                std::to_string(tok.size()) + " fields");
      numbers(tok, 0, 2, "DATA");
      ++data_points;
      continue;
    }
    // Header: "Keyword: values".
    const std::string key = tok.front().text;
    if (key == "LineMinPos:" || key == "LineMaxPos:") {
      const auto v = numbers(tok, 1, 2, key.substr(0, key.size() - 1));
      (key == "LineMinPos:" ? plan.min : plan.max) = Vec2(v[0] / 1000.0, v[1] / 1000.0);
      (key == "LineMinPos:" ? have_min : have_max) = true;
      continue;
    }
    if (key != "Cairn:") continue;  // MapInfo, MinPos, NumLines, ...: nothing the simulator needs
    std::vector<Token> c(tok.begin() + 1, tok.end());
    if (c.size() < 7 || c[5].text != "ICON")
      throw InputError(path, line_no, "Cairn: expected 'type x y heading \"description\" ICON \"name\"'");
    const std::string type = c[0].text, name = c[6].text;
    const auto xyz = numbers(c, 1, 3, "Cairn " + type);
    const Pose2 pose{xyz[0] / 1000.0, xyz[1] / 1000.0, NormalizeAngle(DegToRad(xyz[2]))};
    if (type == "RobotHome") {
      if (plan.home) result.warnings.push_back(path + ":" + std::to_string(line_no) +
                                               ": second RobotHome '" + name + "' replaces the first");
      plan.home = pose;
    } else if (type == "GoalWithHeading" || type == "Goal") {
      const long n = RouteNumber(name);
      if (n < 0) {
        result.warnings.push_back(path + ":" + std::to_string(line_no) + ": Cairn " + type + " '" + name +
                                  "' is not a route point (wpNN); ignored");
      } else {
        if (route.count(n))
          throw InputError(path, line_no, "route point '" + name + "' has the same number as an earlier one");
        route.insert({n, {line_no, Waypoint{name, pose}}});
      }
    } else if (type == "Room" || type == "Doorway") {
      const auto v = numbers(c, 7, 4, "Cairn " + type + " '" + name + "' (x1 y1 x2 y2)");
      const Vec2 a(v[0] / 1000.0, v[1] / 1000.0), b(v[2] / 1000.0, v[3] / 1000.0);
      if (type == "Room") {
        // ARIA rotates a sector's rectangle by theta about the map origin; the
        // room is the axis-aligned box around the rotated rectangle.
        const Pose2 rot{0, 0, pose.theta};
        const Vec2 c[] = {rot * a, rot * Vec2(b.x(), a.y()), rot * b, rot * Vec2(a.x(), b.y())};
        Vec2 lo = c[0], hi = c[0];
        for (const Vec2& p : c) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
        plan.rooms.push_back({name, lo, hi});
      } else {
        plan.doorways.push_back({name, {a, b}});
      }
    } else {
      result.warnings.push_back(path + ":" + std::to_string(line_no) + ": Cairn type '" + type + "' ('" +
                                name + "') is not used by cogmap; ignored");
    }
  }
  if (line_no == 0) throw InputError(path, 0, "empty file (not an ARIA 2D-Map)");
  for (auto& [n, lw] : route) plan.route.push_back(lw.second);
  if (data_points > 0)
    result.warnings.push_back(path + ": " + std::to_string(data_points) +
                              " DATA points ignored (cogmap simulates the LINES only)");
  if (!have_min || !have_max) {
    Vec2 lo(0, 0), hi(0, 0);
    for (size_t i = 0; i < plan.walls.size(); ++i) {
      const auto& w = plan.walls[i];
      if (i == 0) lo = hi = w.a;
      lo = lo.cwiseMin(w.a).cwiseMin(w.b);
      hi = hi.cwiseMax(w.a).cwiseMax(w.b);
    }
    if (!have_min) plan.min = lo;
    if (!have_max) plan.max = hi;
  }
  return result;
}

WorldReadResult ReadAriaMap(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "cannot open the world file");
  std::stringstream ss;
  ss << f.rdbuf();
  return ParseAriaMap(ss.str(), path);
}

std::string FormatAriaMap(const FloorPlan& plan) {
  auto mm = [](double m) { return std::llround(m * 1000.0); };
  auto deg = [](double rad) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", RadToDeg(NormalizeAngle(rad)));
    return std::string(b);
  };
  Vec2 lo = plan.min, hi = plan.max;
  if (lo == hi) {
    for (size_t i = 0; i < plan.walls.size(); ++i) {
      const auto& w = plan.walls[i];
      if (i == 0) lo = hi = w.a;
      lo = lo.cwiseMin(w.a).cwiseMin(w.b);
      hi = hi.cwiseMax(w.a).cwiseMax(w.b);
    }
  }
  std::ostringstream out;
  out << "2D-Map\n";
  out << "LineMinPos: " << mm(lo.x()) << " " << mm(lo.y()) << "\n";
  out << "LineMaxPos: " << mm(hi.x()) << " " << mm(hi.y()) << "\n";
  out << "NumLines: " << plan.walls.size() << "\n";
  out << "MapInfo: SectorType Name=Room \"Label=Room\" \"Desc=Ground-truth room extent\" Shape=Plain\n";
  out << "MapInfo: BoundaryType Name=Doorway \"Label=Doorway\" \"Desc=Ground-truth door opening\"\n";
  if (plan.home)
    out << "Cairn: RobotHome " << mm(plan.home->x) << " " << mm(plan.home->y) << " " << deg(plan.home->theta)
        << " \"\" ICON \"Home\"\n";
  const int digits = plan.route.size() >= 100 ? (plan.route.size() >= 1000 ? 4 : 3) : 2;
  bool all_wp = true;
  long last = -1;
  for (const auto& wp : plan.route) {
    const long n = RouteNumber(wp.name);
    if (n <= last) all_wp = false;
    last = n;
  }
  for (size_t i = 0; i < plan.route.size(); ++i) {
    const auto& wp = plan.route[i];
    char name[32];
    std::snprintf(name, sizeof name, "wp%0*zu", digits, i + 1);
    out << "Cairn: GoalWithHeading " << mm(wp.pose.x) << " " << mm(wp.pose.y) << " " << deg(wp.pose.theta)
        << " \"\" ICON \"" << (all_wp ? wp.name : std::string(name)) << "\"\n";
  }
  for (const auto& r : plan.rooms) {
    const Vec2 c = 0.5 * (r.min + r.max);
    out << "Cairn: Room " << mm(c.x()) << " " << mm(c.y()) << " 0.0 \"\" ICON \"" << r.name << "\" "
        << mm(r.min.x()) << " " << mm(r.min.y()) << " " << mm(r.max.x()) << " " << mm(r.max.y()) << "\n";
  }
  for (const auto& d : plan.doorways) {
    const Vec2 c = 0.5 * (d.line.a + d.line.b);
    out << "Cairn: Doorway " << mm(c.x()) << " " << mm(c.y()) << " 0.0 \"\" ICON \"" << d.name << "\" "
        << mm(d.line.a.x()) << " " << mm(d.line.a.y()) << " " << mm(d.line.b.x()) << " " << mm(d.line.b.y())
        << "\n";
  }
  out << "LINES\n";
  for (const auto& w : plan.walls)
    out << mm(w.a.x()) << " " << mm(w.a.y()) << " " << mm(w.b.x()) << " " << mm(w.b.y()) << "\n";
  out << "DATA\n";
  return out.str();
}

void WriteAriaMap(const std::string& path, const FloorPlan& plan) {
  WriteFileAtomically(path, FormatAriaMap(plan));
}

RoomLabels RoomLabelsFromSegmentation(const RgbImage& img, double m_per_pixel, double min_room_m2) {
  if (!(m_per_pixel > 0)) throw InputError("room segmentation: metres per pixel must be positive");
  const int W = img.width(), H = img.height();
  RoomLabels out;
  out.cell_m = m_per_pixel;
  out.width = W;
  out.height = H;
  out.label.assign(static_cast<size_t>(W) * H, -1);
  auto room_colour = [](const Rgb& c) {
    return (c.r == 255 && c.g == 255 && c.b == 255) || c.r != c.g || c.g != c.b;
  };
  // Cell (x, y up) of image pixel (x, row): y = H - 1 - row.
  auto cell = [&](int x, int row) { return static_cast<size_t>(H - 1 - row) * W + x; };
  const int64_t min_cells = static_cast<int64_t>(std::ceil(min_room_m2 / (m_per_pixel * m_per_pixel)));
  std::vector<std::pair<int, int>> stack, region;
  int next = 0;
  for (int row = 0; row < H; ++row)
    for (int x = 0; x < W; ++x) {
      if (out.label[cell(x, row)] != -1 || !room_colour(img.at(x, row))) continue;
      // Flood the region of this pixel's colour (4-connected).
      const Rgb c = img.at(x, row);
      region.clear();
      stack.assign(1, {x, row});
      out.label[cell(x, row)] = next;
      while (!stack.empty()) {
        const auto [px, py] = stack.back();
        stack.pop_back();
        region.push_back({px, py});
        const int nb[4][2] = {{px + 1, py}, {px - 1, py}, {px, py + 1}, {px, py - 1}};
        for (const auto& n : nb) {
          if (!img.Inside(n[0], n[1]) || !(img.at(n[0], n[1]) == c) || out.label[cell(n[0], n[1])] != -1) continue;
          out.label[cell(n[0], n[1])] = next;
          stack.push_back({n[0], n[1]});
        }
      }
      if (static_cast<int64_t>(region.size()) < min_cells) {
        // Too small for a room: no room, and never flooded again (-2 until the end).
        for (const auto& [px, py] : region) out.label[cell(px, py)] = -2;
        continue;
      }
      out.names.push_back("room " + std::to_string(next + 1));
      out.cells.push_back(static_cast<int64_t>(region.size()));
      ++next;
    }
  for (int32_t& l : out.label) l = std::max(l, -1);
  return out;
}

RoomLabels ReadRoomSegmentation(const std::string& path, const BitmapWorldOptions& bitmap) {
  RoomLabels out = RoomLabelsFromSegmentation(ReadRgbPng(path), bitmap.m_per_pixel);
  if (out.empty())
    throw InputError(path, 0, "no rooms in the segmentation image (a room is a region of white or coloured pixels)");
  return out;
}

FloorPlan FloorPlanFromOccupancy(const GreyImage& img, const BitmapWorldOptions& o) {
  const int W = img.width, H = img.height;
  const double m = o.m_per_pixel;
  if (!(m > 0)) throw InputError("bitmap world: metres per pixel must be positive");
  // Beyond the image is a wall: the world is closed by the image's border
  // (free pixels on it get a wall; a grey outside touching it gets none).
  auto occ = [&](int x, int y) {
    return x < 0 || y < 0 || x >= W || y >= H || img.pixels[static_cast<size_t>(y) * W + x] < o.occupied_below;
  };
  FloorPlan plan;
  // Horizontal edges: the top of row y (between rows y-1 and y), y = 0..H.
  for (int y = 0; y <= H; ++y) {
    const double wy = (H - y) * m;
    int run = -1;
    for (int x = 0; x <= W; ++x) {
      const bool edge = x < W && occ(x, y - 1) != occ(x, y);
      if (edge && run < 0) run = x;
      // A run also ends where the occupied side switches (two separate walls).
      if (run >= 0 && (!edge || occ(x, y) != occ(run, y))) {
        plan.walls.push_back({{run * m, wy}, {x * m, wy}});
        run = edge ? x : -1;
      }
    }
  }
  // Vertical edges: the left of column x, x = 0..W.
  for (int x = 0; x <= W; ++x) {
    const double wx = x * m;
    int run = -1;
    for (int y = 0; y <= H; ++y) {
      const bool edge = y < H && occ(x - 1, y) != occ(x, y);
      if (edge && run < 0) run = y;
      if (run >= 0 && (!edge || occ(x, y) != occ(x, run))) {
        plan.walls.push_back({{wx, (H - run) * m}, {wx, (H - y) * m}});
        run = edge ? y : -1;
      }
    }
  }
  plan.min = Vec2(0, 0);
  plan.max = Vec2(W * m, H * m);
  // Home: the free pixel farthest from any occupied one (3-4 chamfer distance).
  if (W > 0 && H > 0) {
    const int kInf = 1 << 29;
    std::vector<int> d(static_cast<size_t>(W) * H);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) d[static_cast<size_t>(y) * W + x] = occ(x, y) ? 0 : kInf;
    auto at = [&](int x, int y) -> int& { return d[static_cast<size_t>(y) * W + x]; };
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        int& v = at(x, y);
        // The border counts as a wall (3 from a pixel on it).
        if (x == 0 || y == 0 || x + 1 == W || y + 1 == H) v = std::min(v, 3);
        if (x > 0) v = std::min(v, at(x - 1, y) + 3);
        if (y > 0) v = std::min(v, at(x, y - 1) + 3);
        if (x > 0 && y > 0) v = std::min(v, at(x - 1, y - 1) + 4);
        if (x + 1 < W && y > 0) v = std::min(v, at(x + 1, y - 1) + 4);
      }
    for (int y = H - 1; y >= 0; --y)
      for (int x = W - 1; x >= 0; --x) {
        int& v = at(x, y);
        if (x + 1 < W) v = std::min(v, at(x + 1, y) + 3);
        if (y + 1 < H) v = std::min(v, at(x, y + 1) + 3);
        if (x + 1 < W && y + 1 < H) v = std::min(v, at(x + 1, y + 1) + 4);
        if (x > 0 && y + 1 < H) v = std::min(v, at(x - 1, y + 1) + 4);
      }
    int best = -1, bx = 0, by = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (img.pixels[static_cast<size_t>(y) * W + x] >= o.free_above && at(x, y) > best && at(x, y) < kInf) {
          best = at(x, y);
          bx = x;
          by = y;
        }
    if (best > 0) plan.home = Pose2{(bx + 0.5) * m, (H - by - 0.5) * m, 0.0};
  }
  return plan;
}

WorldReadResult ReadMapServerWorld(const std::string& yaml_path) {
  const MapServerYaml yaml = ReadMapServerYaml(yaml_path);
  std::filesystem::path image(yaml.image);
  if (image.is_relative()) image = std::filesystem::path(yaml_path).parent_path() / image;
  std::string ext = image.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  GreyImage pixels;
  int max_value = 255;
  if (ext == ".png") {
    pixels = ReadGreyPng(image.string());
  } else if (ext == ".pgm") {
    PgmImage pgm = ReadPgm(image.string());
    pixels = GreyImage{pgm.width, pgm.height, std::move(pgm.pixels)};
    max_value = pgm.max_value;
  } else {
    throw InputError(yaml_path, 0, "image '" + yaml.image + "': cogmap reads map_server images as PGM or PNG");
  }
  // map_server's classification (as ReadMapServer in grid_io.cc), drawn as a
  // bitmap world: occupied black, free white, unknown grey (neither).
  constexpr uint8_t kWall = 0, kFree = 255, kUnknown = 205;
  GreyImage grey{pixels.width, pixels.height, std::vector<uint8_t>(pixels.pixels.size(), kUnknown)};
  for (size_t i = 0; i < pixels.pixels.size(); ++i) {
    const double v = 255.0 * pixels.pixels[i] / max_value;
    const double p = yaml.negate ? v / 255.0 : (255.0 - v) / 255.0;
    if (yaml.mode == "raw") {
      grey.pixels[i] = v >= 100.0 ? kWall : v == 0.0 ? kFree : kUnknown;
    } else if (p > yaml.occupied_thresh) {
      grey.pixels[i] = kWall;
    } else if (p < yaml.free_thresh) {
      grey.pixels[i] = kFree;
    }
  }
  BitmapWorldOptions o;
  o.m_per_pixel = yaml.resolution;
  o.occupied_below = kUnknown;  // only occupied pixels are walls (unknown ones are not free either: never home)
  WorldReadResult r;
  r.plan = FloorPlanFromOccupancy(grey, o);
  // Image frame (lower-left corner at 0, 0) -> map frame.
  const Pose2 map_from_image{yaml.origin.x(), yaml.origin.y(), yaml.origin_yaw};
  auto place = [&](const Vec2& v) { return map_from_image * v; };
  for (auto& w : r.plan.walls) w = {place(w.a), place(w.b)};
  if (r.plan.home) r.plan.home = map_from_image * *r.plan.home;
  const Vec2 corners[] = {place(r.plan.min), place({r.plan.max.x(), r.plan.min.y()}), place(r.plan.max),
                          place({r.plan.min.x(), r.plan.max.y()})};
  r.plan.min = r.plan.max = corners[0];
  for (const Vec2& c : corners) {
    r.plan.min = r.plan.min.cwiseMin(c);
    r.plan.max = r.plan.max.cwiseMax(c);
  }
  if (r.plan.walls.empty()) r.warnings.push_back(yaml_path + ": no occupied cells in " + image.string() + ", so no walls");
  return r;
}

WorldReadResult ReadWorld(const std::string& path, const BitmapWorldOptions& bitmap) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  auto ends_with = [&](const std::string& e) {
    return lower.size() >= e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0;
  };
  if (ends_with(".yaml") || ends_with(".yml")) return ReadMapServerWorld(path);
  if (lower.size() >= 4 && lower.compare(lower.size() - 4, 4, ".png") == 0) {
    WorldReadResult r;
    r.plan = FloorPlanFromOccupancy(ReadGreyPng(path), bitmap);
    if (r.plan.walls.empty()) r.warnings.push_back(path + ": no occupied (dark) pixels, so no walls");
    return r;
  }
  return ReadAriaMap(path);
}

}  // namespace cogmap::io
