#include "cogmap/draw/drawing.h"


#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
// Last: every drawing-stack call below goes through the table loaded on
// first use (cairo_api.h).
#include "cogmap/draw/cairo_api_calls.h"

namespace cogmap::draw {

namespace {

// The largest raster side cairo's image surfaces take.
constexpr int kMaxRasterSide = 32767;

void SetColour(cairo_t* cr, const Colour& c) { cairo_set_source_rgba(cr, c.r, c.g, c.b, c.a); }

void ApplyStroke(cairo_t* cr, const Stroke& s) {
  SetColour(cr, s.colour);
  cairo_set_line_width(cr, s.width_px);
  cairo_set_line_cap(cr, s.round ? CAIRO_LINE_CAP_ROUND : CAIRO_LINE_CAP_BUTT);
  cairo_set_line_join(cr, s.round ? CAIRO_LINE_JOIN_ROUND : CAIRO_LINE_JOIN_MITER);
  cairo_set_dash(cr, s.dash_px.empty() ? nullptr : s.dash_px.data(), static_cast<int>(s.dash_px.size()), 0.0);
}

// The font options of every text layout (no hinting of metrics), so that a
// label measures the same in SVG, PNG and PDF. Every option is set, so that
// no surface's own defaults merge into them: pango keys its fonts by these
// options, and a font it has not seen with them costs a fontconfig sort (on
// threads of pango's own). The measuring surface and the SVG surface merged
// different antialiasing into them: every font was sorted twice (nine_rooms'
// map: 44 threads started, 24 with this).
void SetFontOptions(PangoContext* context) {
  cairo_font_options_t* fo = cairo_font_options_create();
  cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
  pango_cairo_context_set_font_options(context, fo);
  cairo_font_options_destroy(fo);
}

PangoLayout* LayoutIn(PangoContext* context, const std::string& text, const Font& font) {
  PangoLayout* layout = pango_layout_new(context);
  PangoFontDescription* desc = pango_font_description_from_string("DejaVu Sans, sans-serif");
  pango_font_description_set_absolute_size(desc, font.size_px * PANGO_SCALE);
  pango_font_description_set_weight(desc, font.bold ? PANGO_WEIGHT_BOLD : PANGO_WEIGHT_NORMAL);
  pango_layout_set_font_description(layout, desc);
  pango_font_description_free(desc);
  pango_layout_set_text(layout, text.c_str(), static_cast<int>(text.size()));
  return layout;
}

// The faces every picture is drawn in: DejaVu Sans (Debian's
// fonts-dejavu-core), loaded from their files into a font configuration of
// their own. Pictures then look the same on every machine, whatever other
// fonts it has, and a run does not read and parse the system's whole font
// configuration (fontconfig's XML and its cache of every installed font:
// about 8 ms of a 80 ms nine_rooms run). Text with a character these faces
// lack (a file or room name in another script) is laid out with the system
// configuration instead.
constexpr const char* kFaceFiles[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                                      "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf"};

// Pango, once per process: one font map for every thread (pango's default
// font map is one per thread, each reading the font configuration and sorting
// each font anew), used under one lock (a font map is not for two threads at
// once), and warmed on a thread of its own while a run maps (PrepareFonts).
struct Fonts {
  std::mutex mutex;
  bool own_tried = false;
  PangoFontMap* own = nullptr;     // the bundled faces (null: not installed)
  FcCharSet* covered = nullptr;    // the characters they have
  PangoFontMap* system = nullptr;  // the system's font configuration
  cairo_surface_t* measure_surface = nullptr;
  cairo_t* measure_cr = nullptr;
  PangoContext* measure[2] = {nullptr, nullptr};  // own, system
  std::thread warming;
  std::thread loading;  // PrepareLibraries
  // With the lock held. The font map for 'text': the bundled faces when
  // they have every character of it, else the system's.
  bool Own(const std::string& text) {
    if (!own_tried) {
      own_tried = true;
      FcConfig* config = FcConfigCreate();
      bool all = config != nullptr;
      for (const char* file : kFaceFiles)
        all = all && FcConfigAppFontAddFile(config, reinterpret_cast<const FcChar8*>(file));
      FcFontSet* set = all ? FcConfigGetFonts(config, FcSetApplication) : nullptr;
      if (set && set->nfont > 0) {
        covered = FcCharSetCreate();
        for (int i = 0; i < set->nfont; ++i) {
          FcCharSet* cs = nullptr;
          if (FcPatternGetCharSet(set->fonts[i], FC_CHARSET, 0, &cs) == FcResultMatch) FcCharSetMerge(covered, cs, nullptr);
        }
        // Also the process's current configuration, set before the first
        // pango font map: pango starts a thread that initialises fontconfig
        // (FcInit), which otherwise loads the system's configuration (its
        // XML and its cache of every installed font) whether or not any
        // text needs it. The system's is loaded for the text these faces
        // lack only (Map).
        FcConfigSetCurrent(config);
        own = pango_cairo_font_map_new_for_font_type(CAIRO_FONT_TYPE_FT);
        if (own && PANGO_IS_FC_FONT_MAP(own)) {
          pango_fc_font_map_set_config(PANGO_FC_FONT_MAP(own), config);
        } else if (own) {
          g_object_unref(own);
          own = nullptr;
        }
      }
      if (config) FcConfigDestroy(config);  // the font map holds its own reference
    }
    if (!own) return false;
    // UTF-8 decoded leniently: a malformed byte counts as a character the
    // faces lack (pango then shows what the system's fonts make of it).
    for (size_t i = 0; i < text.size();) {
      const unsigned char c = static_cast<unsigned char>(text[i]);
      const int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
      if (n == 0 || i + n > text.size()) return false;
      FcChar32 cp = n == 1 ? c : c & (0x7F >> n);
      for (int k = 1; k < n; ++k) {
        const unsigned char d = static_cast<unsigned char>(text[i + k]);
        if ((d >> 6) != 2) return false;
        cp = (cp << 6) | (d & 0x3F);
      }
      if (cp >= 0x20 && !FcCharSetHasChar(covered, cp)) return false;
      i += n;
    }
    return true;
  }
  PangoFontMap* Map(bool own_faces) {
    if (own_faces) return own;
    if (!system) {
      system = pango_cairo_font_map_new();
      // The current configuration is the bundled faces' (Own): the
      // system's is loaded for this map alone.
      if (own_tried && covered && system && PANGO_IS_FC_FONT_MAP(system)) {
        if (FcConfig* config = FcInitLoadConfigAndFonts()) {
          pango_fc_font_map_set_config(PANGO_FC_FONT_MAP(system), config);
          FcConfigDestroy(config);  // the font map holds its own reference
        }
      }
    }
    return system;
  }
  PangoContext* Measure(const std::string& text) {
    const bool mine = Own(text);
    PangoContext*& m = measure[mine ? 0 : 1];
    if (!m) {
      if (!measure_surface) {
        measure_surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, 1, 1);
        measure_cr = cairo_create(measure_surface);
      }
      m = pango_font_map_create_context(Map(mine));
      pango_cairo_update_context(measure_cr, m);
      SetFontOptions(m);
    }
    return m;
  }
};

// Never destroyed before the threads that draw (nor the warming thread,
// joined at exit): the font map and contexts live as long as the process.
Fonts& TheFonts() {
  static Fonts* fonts = new Fonts;
  static struct JoinAtExit {
    ~JoinAtExit() {
      if (fonts->warming.joinable()) fonts->warming.join();
      if (fonts->loading.joinable()) fonts->loading.join();
    }
  } join_at_exit;
  return *fonts;
}

// A text layout on a cairo surface, in one pango context per cairo_t (kept
// on it), brought up to date with its transformation for each layout. With
// the fonts' lock held.
PangoLayout* MakeLayout(cairo_t* cr, const std::string& text, const Font& font) {
  static const cairo_user_data_key_t kContextKey[2] = {};
  const bool mine = TheFonts().Own(text);
  const cairo_user_data_key_t* key = &kContextKey[mine ? 0 : 1];
  auto* context = static_cast<PangoContext*>(cairo_get_user_data(cr, key));
  if (!context) {
    context = pango_font_map_create_context(TheFonts().Map(mine));
    SetFontOptions(context);
    // Released when the cairo_t goes, which is never while this thread
    // holds the lock (a drawing's steps take it one at a time).
    cairo_set_user_data(cr, key, context, [](void* c) {
      std::lock_guard<std::mutex> lock(TheFonts().mutex);
      g_object_unref(c);
    });
  }
  pango_cairo_update_context(cr, context);
  return LayoutIn(context, text, font);
}

cairo_status_t AppendBytes(void* closure, const unsigned char* data, unsigned int length) {
  std::ostream& out = *static_cast<std::ostream*>(closure);
  out.write(reinterpret_cast<const char*>(data), length);
  return out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

// Row y of a CAIRO_FORMAT_RGB24 image surface's pixels as 8-bit RGB triples.
void SurfaceRowToRgb(cairo_surface_t* surface, int y, uint8_t* rgb) {
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const int w = cairo_image_surface_get_width(surface);
  const auto* px = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
  for (int x = 0; x < w; ++x) {
    rgb[3 * x] = static_cast<uint8_t>(px[x] >> 16);
    rgb[3 * x + 1] = static_cast<uint8_t>(px[x] >> 8);
    rgb[3 * x + 2] = static_cast<uint8_t>(px[x]);
  }
}

void CheckStatus(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cairo: ") + what + ": " + cairo_status_to_string(status));
}

void RasterSize(double width, double height, int* w, int* h) {
  *w = std::max(1, static_cast<int>(std::ceil(width - 1e-9)));
  *h = std::max(1, static_cast<int>(std::ceil(height - 1e-9)));
  if (*w > kMaxRasterSide || *h > kMaxRasterSide)
    throw std::invalid_argument("drawing of " + std::to_string(*w) + " x " + std::to_string(*h) +
                                " px is larger than a raster can be (" + std::to_string(kMaxRasterSide) + ")");
}

}  // namespace

Format FormatOfPath(const std::string& path) {
  const auto dot = path.rfind('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == "svg") return Format::kSvg;
  if (ext == "png") return Format::kPng;
  if (ext == "pdf") return Format::kPdf;
  throw InputError(path + ": a picture is written as .svg, .png or .pdf");
}

Drawing::Drawing(double width_px, double height_px, Colour background)
    : width_(std::max(1.0, width_px)),
      height_(std::max(1.0, height_px)),
      background_(background),
      steps_(std::make_shared<std::vector<Step>>()) {}

void Drawing::Line(const Vec2& a, const Vec2& b, const Stroke& stroke) { Stroked({a, b}, stroke, false); }

namespace {

// The points of a polyline that draw something: a point within a quarter of a
// drawing pixel of the last one kept is dropped (the line passes within a
// quarter pixel of it anyway). A robot path logged every few centimetres and
// drawn at metres a pixel keeps a point per pixel, not thousands: cairo's SVG
// surface records every point of the page before writing it.
std::vector<Vec2> Thinned(const std::vector<Vec2>& points) {
  if (points.size() < 3) return points;
  std::vector<Vec2> out;
  out.reserve(points.size());
  out.push_back(points.front());
  for (size_t i = 1; i + 1 < points.size(); ++i)
    if ((points[i] - out.back()).squaredNorm() >= 0.0625) out.push_back(points[i]);
  out.push_back(points.back());
  return out;
}

}  // namespace

void Drawing::Polyline(const std::vector<Vec2>& input, const Stroke& stroke, bool closed) {
  if (input.size() < 2) return;
  Stroked(Thinned(input), stroke, closed);
}

namespace {

bool SameStroke(const Stroke& a, const Stroke& b) {
  return a.colour.r == b.colour.r && a.colour.g == b.colour.g && a.colour.b == b.colour.b &&
         a.colour.a == b.colour.a && a.width_px == b.width_px && a.dash_px == b.dash_px && a.round == b.round;
}

}  // namespace

// Lines drawn one after another with the same opaque stroke are one cairo
// path of several subpaths, stroked once: what they paint is the same (an
// opaque stroke painted over itself looks as painted once; a dash pattern
// starts again at each subpath as at each path), but the SVG holds one
// <path> element and one style for them instead of one per line (a
// 1000-room floor plan has some 13,000 walls; cairo keeps the page in
// memory until it is written). Translucent strokes stay one path each, since
// their overlaps would darken.
struct Drawing::StrokeBatch {
  Stroke stroke;
  std::vector<std::vector<Vec2>> lines;
  std::vector<bool> closed;
};

void Drawing::Stroked(std::vector<Vec2> points, const Stroke& stroke, bool closed) {
  std::shared_ptr<StrokeBatch> batch = open_batch_.lock();
  if (batch && open_batch_step_ + 1 == steps_->size() && stroke.colour.a >= 1.0 &&
      SameStroke(batch->stroke, stroke)) {
    batch->lines.push_back(std::move(points));
    batch->closed.push_back(closed);
    return;
  }
  batch = std::make_shared<StrokeBatch>();
  batch->stroke = stroke;
  batch->lines.push_back(std::move(points));
  batch->closed.push_back(closed);
  open_batch_ = batch;
  open_batch_step_ = steps_->size();
  steps_->push_back([batch](cairo_t* cr) {
    ApplyStroke(cr, batch->stroke);
    for (size_t k = 0; k < batch->lines.size(); ++k) {
      const auto& points = batch->lines[k];
      cairo_move_to(cr, points[0].x(), points[0].y());
      for (size_t i = 1; i < points.size(); ++i) cairo_line_to(cr, points[i].x(), points[i].y());
      if (batch->closed[k]) cairo_close_path(cr);
    }
    cairo_stroke(cr);
  });
}

void Drawing::Polygon(const std::vector<Vec2>& input, Colour fill, const Stroke& outline) {
  if (input.size() < 3) return;
  // Thinned as a polyline is: a room outline traced on a 0.1 m grid and
  // drawn at a few pixels a room keeps a point per quarter pixel.
  std::vector<Vec2> thinned = Thinned(input);
  std::vector<Vec2> points = thinned.size() >= 3 ? std::move(thinned) : input;
  steps_->push_back([points = std::move(points), fill, outline](cairo_t* cr) {
    cairo_move_to(cr, points[0].x(), points[0].y());
    for (size_t i = 1; i < points.size(); ++i) cairo_line_to(cr, points[i].x(), points[i].y());
    cairo_close_path(cr);
    SetColour(cr, fill);
    if (outline.width_px > 0) {
      cairo_fill_preserve(cr);
      ApplyStroke(cr, outline);
      cairo_stroke(cr);
    } else {
      cairo_fill(cr);
    }
  });
}

void Drawing::Circle(const Vec2& centre, double radius_px, Colour fill) {
  steps_->push_back([centre, radius_px, fill](cairo_t* cr) {
    cairo_new_sub_path(cr);
    cairo_arc(cr, centre.x(), centre.y(), radius_px, 0, 2 * M_PI);
    SetColour(cr, fill);
    cairo_fill(cr);
  });
}

void Drawing::Rectangle(const Box& box, Colour fill, const Stroke& outline) {
  steps_->push_back([box, fill, outline](cairo_t* cr) {
    cairo_rectangle(cr, box.x0, box.y0, box.width(), box.height());
    SetColour(cr, fill);
    if (outline.width_px > 0) {
      cairo_fill_preserve(cr);
      ApplyStroke(cr, outline);
      cairo_stroke(cr);
    } else {
      cairo_fill(cr);
    }
  });
}

void Drawing::PrepareLibraries() {
  Fonts& f = TheFonts();
  std::lock_guard<std::mutex> lock(f.mutex);
  if (f.loading.joinable() || dl::loaded.load(std::memory_order_acquire)) return;
  f.loading = std::thread([] {
    try {
      dl::Load();
    } catch (const std::exception&) {
      // The first picture drawn raises the same error on its own thread.
    }
  });
}

void Drawing::PrepareFonts(const std::vector<Font>& fonts) {
  Fonts& f = TheFonts();
  std::lock_guard<std::mutex> lock(f.mutex);
  if (f.own_tried || f.warming.joinable()) return;
  // Text measured or drawn meanwhile waits for the lock (or, taking it
  // first, loads its font itself): the same fonts either way.
  f.warming = std::thread([&f, fonts] {
    std::lock_guard<std::mutex> held(f.mutex);
    try {
      PangoContext* context = f.Measure("Ag");
      for (const Font& font : fonts) {
        PangoLayout* layout = LayoutIn(context, "Ag", font);
        PangoRectangle logical;
        pango_layout_get_extents(layout, nullptr, &logical);
        g_object_unref(layout);
      }
    } catch (const std::exception&) {
      // The drawing stack could not be loaded (cairo_api.h): the first
      // picture drawn raises the same error on its own thread.
    }
  });
}

Box Drawing::MeasureText(const std::string& text, const Font& font) {
  Fonts& f = TheFonts();
  std::lock_guard<std::mutex> lock(f.mutex);
  PangoLayout* layout = LayoutIn(f.Measure(text), text, font);
  PangoRectangle logical;
  pango_layout_get_extents(layout, nullptr, &logical);
  g_object_unref(layout);
  return Box{0, 0, static_cast<double>(logical.width) / PANGO_SCALE, static_cast<double>(logical.height) / PANGO_SCALE};
}

Box Drawing::Text(const Vec2& at, const std::string& text, const Font& font, Colour colour, Align align,
                  VAlign valign) {
  const Box size = MeasureText(text, font);
  double x = at.x(), y = at.y();
  if (align == Align::kCenter) x -= size.width() / 2;
  if (align == Align::kRight) x -= size.width();
  if (valign == VAlign::kMiddle) y -= size.height() / 2;
  if (valign == VAlign::kBottom) y -= size.height();
  steps_->push_back([x, y, text, font, colour](cairo_t* cr) {
    std::lock_guard<std::mutex> lock(TheFonts().mutex);
    PangoLayout* layout = MakeLayout(cr, text, font);
    SetColour(cr, colour);
    cairo_move_to(cr, x, y);
    pango_cairo_show_layout(cr, layout);
    g_object_unref(layout);
  });
  return Box{x, y, x + size.width(), y + size.height()};
}

void Drawing::Image(const io::RgbImage& image, double x, double y, double scale) {
  if (image.width() <= 0 || image.height() <= 0) return;
  // Cairo's RGB24: one 32-bit word per pixel, native endian, 0x00RRGGBB.
  auto data = std::make_shared<std::vector<uint32_t>>(static_cast<size_t>(image.width()) * image.height());
  for (int j = 0; j < image.height(); ++j)
    for (int i = 0; i < image.width(); ++i) {
      const io::Rgb c = image.at(i, j);
      (*data)[static_cast<size_t>(j) * image.width() + i] =
          (static_cast<uint32_t>(c.r) << 16) | (static_cast<uint32_t>(c.g) << 8) | c.b;
    }
  const int w = image.width(), h = image.height();
  steps_->push_back([data, w, h, x, y, scale](cairo_t* cr) {
    cairo_surface_t* s = cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(data->data()),
                                                             CAIRO_FORMAT_RGB24, w, h, w * 4);
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, scale, scale);
    cairo_set_source_surface(cr, s, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_rectangle(cr, 0, 0, w, h);
    cairo_fill(cr);
    cairo_restore(cr);
    cairo_surface_destroy(s);
  });
}

void Drawing::Place(const Drawing& other, double x, double y, double scale) {
  auto steps = std::make_shared<std::vector<Step>>(*other.steps_);
  const Colour bg = other.background_;
  const double w = other.width_, h = other.height_;
  steps_->push_back([steps, bg, w, h, x, y, scale](cairo_t* cr) {
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, scale, scale);
    cairo_rectangle(cr, 0, 0, w, h);
    cairo_clip(cr);
    if (bg.a > 0) {
      SetColour(cr, bg);
      cairo_paint(cr);
    }
    for (const auto& s : *steps) {
      cairo_save(cr);
      s(cr);
      cairo_restore(cr);
    }
    cairo_restore(cr);
  });
}

void Drawing::Replay(cairo_t* cr) const { Replay(cr, false); }

void Drawing::Replay(cairo_t* cr, bool release) const {
  cairo_save(cr);
  SetColour(cr, background_);
  cairo_rectangle(cr, 0, 0, width_, height_);
  cairo_fill(cr);
  cairo_restore(cr);
  // Released steps go as cairo takes them, unless a copy of this drawing
  // shares them.
  release = release && steps_.use_count() == 1;
  for (auto& s : *steps_) {
    cairo_save(cr);
    s(cr);
    cairo_restore(cr);
    if (release) s = Step();
  }
  if (release) std::vector<Step>().swap(*steps_);
}

void Drawing::EncodeTo(Format format, std::ostream& out) const { EncodeTo(format, out, false); }

void Drawing::EncodeTo(Format format, std::ostream& out, bool release) const {
  std::ostream* bytes = &out;  // cairo writes through AppendBytes as it goes
  cairo_surface_t* surface = nullptr;
  if (format == Format::kSvg) {
    surface = cairo_svg_surface_create_for_stream(AppendBytes, bytes, width_, height_);
    cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_PX);
  } else if (format == Format::kPdf) {
    surface = cairo_pdf_surface_create_for_stream(AppendBytes, bytes, width_, height_);
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "cogmap");
  } else {
    int w = 0, h = 0;
    RasterSize(width_, height_, &w, &h);
    surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  }
  CheckStatus(cairo_surface_status(surface), "surface");
  cairo_t* cr = cairo_create(surface);
  Replay(cr, release);
  const cairo_status_t drawn = cairo_status(cr);
  cairo_destroy(cr);
  if (format == Format::kPng && drawn == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(surface);
    try {
      io::EncodeRgbPngRows(
          cairo_image_surface_get_width(surface), cairo_image_surface_get_height(surface),
          [&](int y, uint8_t* rgb) { SurfaceRowToRgb(surface, y, rgb); }, out);
    } catch (...) {
      cairo_surface_destroy(surface);
      throw;
    }
    cairo_surface_destroy(surface);
    if (!out) CheckStatus(CAIRO_STATUS_WRITE_ERROR, "PNG");
    return;
  }
  cairo_surface_finish(surface);
  const cairo_status_t finished = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  CheckStatus(drawn, "drawing");
  CheckStatus(finished, "finishing");
}

std::string Drawing::Encode(Format format) const {
  std::ostringstream bytes;
  EncodeTo(format, bytes);
  return std::move(bytes).str();
}

io::RgbImage Drawing::Rasterize() const {
  int w = 0, h = 0;
  RasterSize(width_, height_, &w, &h);
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  CheckStatus(cairo_surface_status(surface), "surface");
  cairo_t* cr = cairo_create(surface);
  Replay(cr);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  io::RgbImage out(w, h);
  static_assert(sizeof(io::Rgb) == 3, "RgbImage rows are packed RGB triples");
  for (int j = 0; j < h; ++j) SurfaceRowToRgb(surface, j, reinterpret_cast<uint8_t*>(&out.at(0, j)));
  cairo_surface_destroy(surface);
  return out;
}

void Drawing::Write(const std::string& path) const& { Write(path, false); }

void Drawing::Write(const std::string& path) && { Write(path, true); }

void Drawing::Write(const std::string& path, bool release) const {
  const Format format = FormatOfPath(path);
  // Streamed into the file as cairo writes it: a 1000-room map.svg is some
  // 8 MB, which a string would hold (and double while growing).
  io::WriteFileAtomically(path, [&](std::ostream& out) {
    try {
      EncodeTo(format, out, release);
    } catch (const std::runtime_error&) {
      if (!out) throw InputError(path, 0, "write failed (disk full?)");  // cairo's stream error, said as the file's
      throw;
    }
  });
}

}  // namespace cogmap::draw
