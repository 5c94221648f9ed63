#include "cogmap/draw/map_picture.h"

#include <algorithm>
#include <filesystem>
#include <map>

namespace cogmap::draw {

namespace {

const Colour kPalette[] = {Rgb8(31, 119, 180), Rgb8(214, 39, 40),  Rgb8(44, 160, 44),  Rgb8(148, 103, 189),
                           Rgb8(140, 86, 75),  Rgb8(227, 119, 194), Rgb8(23, 190, 207), Rgb8(188, 189, 34),
                           Rgb8(255, 127, 14), Rgb8(60, 60, 60)};
const Colour kPathColour = Rgb8(185, 185, 185);
const Colour kExitColour = Rgb8(0, 170, 0);
const Colour kGraphColour = Rgb8(255, 136, 0);

}  // namespace

Colour RoomColour(int id) { return kPalette[static_cast<unsigned>(id) % (sizeof(kPalette) / sizeof(kPalette[0]))]; }

MapPicture DrawMasterMap(const io::MasterMap& map, const MapPictureOptions& options) {
  std::vector<LegendItem> legend = {{LegendItem::Kind::kLine, RoomColour(0), "walls (a colour per ASR)"}};
  if (options.path) legend.push_back({LegendItem::Kind::kLine, kPathColour, "robot path"});
  legend.push_back({LegendItem::Kind::kDisc, kExitColour, "exit"});
  if (options.graph) legend.push_back({LegendItem::Kind::kDashed, kGraphColour, "room graph"});
  MapPage page(map.min, map.max, options.picture, legend);
  Drawing d = page.NewDrawing();
  const double k = page.px_per_m();
  // Line widths in pixels, growing a little with the scale (walls 8 cm when
  // that is wider than 2 px).
  const double wall_px = std::clamp(0.08 * k, 2.0, 6.0);
  if (options.path) {
    const Stroke s{kPathColour, std::clamp(0.03 * k, 1.0, 2.5)};
    for (const auto& r : map.rooms) d.Polyline(page.Px(r.path), s);
  }
  for (const auto& r : map.rooms) {
    const Stroke s{RoomColour(r.id), wall_px};
    for (const auto& l : r.walls) d.Polyline(page.Px(l), s);
  }
  std::map<int, const io::MasterRoom*> by_id;
  for (const auto& r : map.rooms) by_id[r.id] = &r;
  if (options.graph) {
    const Stroke s{kGraphColour, std::clamp(0.04 * k, 1.2, 3.0), {6, 4}, false};
    for (const auto& e : map.exits) {
      const auto a = by_id.find(e.from_asr), b = by_id.find(e.to_asr);
      if (a == by_id.end() || b == by_id.end()) continue;
      d.Polyline({page.Px(a->second->label_m), page.Px(e.center_m), page.Px(b->second->label_m)}, s);
    }
  }
  const double exit_r = std::clamp(0.15 * k, 2.5, 8.0);
  for (const auto& e : map.exits) d.Circle(page.Px(e.center_m), exit_r, kExitColour);

  LabelPlacer placer(page.map_box());  // labels stay over the map, off the bands
  for (const auto& b : page.Decorate(d)) placer.Block(b);
  if (options.labels) {
    const Font font{std::clamp(0.45 * k, 11.0, 16.0), true};
    for (const auto& r : map.rooms)
      placer.Label(d, page.Px(r.label_m), "A" + std::to_string(r.id), font, kBlack);
  }
  MapPicture out;
  out.drawing = std::move(d);
  out.px_per_m = k;
  out.scale_bar = page.scale_bar();
  out.map_box = page.map_box();
  out.origin_px = page.Px(Vec2(0, 0));
  out.labels_placed = placer.placed();
  out.labels_dropped = placer.dropped();
  return out;
}

Drawing DrawSideBySide(const io::MasterMap& left, const std::string& left_title, const io::MasterMap& right,
                       const std::string& right_title, const MapPictureOptions& options) {
  MapPictureOptions half = options;
  const double gap = 12;
  half.picture.max_side_px = std::max(64, static_cast<int>((options.picture.max_side_px - gap) / 2));
  half.picture.title = left_title;
  const MapPicture l = DrawMasterMap(left, half);
  half.picture.title = right_title;
  const MapPicture r = DrawMasterMap(right, half);
  Drawing d(l.drawing.width() + gap + r.drawing.width(), std::max(l.drawing.height(), r.drawing.height()));
  d.Place(l.drawing, 0, 0);
  d.Place(r.drawing, l.drawing.width() + gap, 0);
  const double x = l.drawing.width() + gap / 2;
  d.Line(Vec2(x, 0), Vec2(x, d.height()), Stroke{Rgb8(180, 180, 180), 1, {}, false});
  return d;
}

std::vector<std::string> WriteMasterMapPictures(const std::string& dir, const io::MasterMap& map, bool svg, bool png,
                                                bool pdf, const MapPictureOptions& options) {
  std::vector<std::string> written;
  if (!svg && !png && !pdf) return written;
  const Drawing d = DrawMasterMap(map, options).drawing;
  const std::string base = (std::filesystem::path(dir) / "map").string();
  for (const auto& [want, ext] : {std::pair{svg, ".svg"}, std::pair{png, ".png"}, std::pair{pdf, ".pdf"}})
    if (want) {
      d.Write(base + ext);
      written.push_back(base + ext);
    }
  return written;
}

}  // namespace cogmap::draw
