#pragma once
// The drawing stack (cairo, pango, fontconfig, GObject and the thirty-odd
// libraries they pull in) loaded by dlopen when a picture is first measured or
// drawn, not by the dynamic loader when the program starts: a run that draws
// loads it on the font-warming thread while it maps (Drawing::PrepareFonts),
// one that draws nothing never loads it (about 3 ms of every process start,
// 4 % of a whole nine_rooms run). drawing.cc calls the functions through
// the table below (cairo_api_calls.h); the headers give their types.
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fontconfig/fontconfig.h>
#include <pango/pangocairo.h>
#include <pango/pangofc-fontmap.h>

#include <atomic>

namespace cogmap::draw::dl {

// Every function drawing.cc calls (cairo_api_calls.h has a macro for each).
#define COGMAP_DRAW_FUNCTIONS(X) \
  X(FcCharSetCreate) \
  X(FcCharSetHasChar) \
  X(FcCharSetMerge) \
  X(FcConfigAppFontAddFile) \
  X(FcConfigCreate) \
  X(FcConfigDestroy) \
  X(FcConfigGetFonts) \
  X(FcConfigSetCurrent) \
  X(FcInitLoadConfigAndFonts) \
  X(FcPatternGetCharSet) \
  X(cairo_arc) \
  X(cairo_clip) \
  X(cairo_close_path) \
  X(cairo_create) \
  X(cairo_destroy) \
  X(cairo_fill) \
  X(cairo_fill_preserve) \
  X(cairo_font_options_create) \
  X(cairo_font_options_destroy) \
  X(cairo_font_options_set_antialias) \
  X(cairo_font_options_set_hint_metrics) \
  X(cairo_font_options_set_hint_style) \
  X(cairo_get_source) \
  X(cairo_get_user_data) \
  X(cairo_image_surface_create) \
  X(cairo_image_surface_create_for_data) \
  X(cairo_image_surface_get_data) \
  X(cairo_image_surface_get_height) \
  X(cairo_image_surface_get_stride) \
  X(cairo_image_surface_get_width) \
  X(cairo_line_to) \
  X(cairo_move_to) \
  X(cairo_new_sub_path) \
  X(cairo_paint) \
  X(cairo_pattern_set_filter) \
  X(cairo_pdf_surface_create_for_stream) \
  X(cairo_pdf_surface_set_metadata) \
  X(cairo_rectangle) \
  X(cairo_restore) \
  X(cairo_save) \
  X(cairo_scale) \
  X(cairo_set_dash) \
  X(cairo_set_line_cap) \
  X(cairo_set_line_join) \
  X(cairo_set_line_width) \
  X(cairo_set_source_rgba) \
  X(cairo_set_source_surface) \
  X(cairo_set_user_data) \
  X(cairo_status) \
  X(cairo_status_to_string) \
  X(cairo_stroke) \
  X(cairo_surface_destroy) \
  X(cairo_surface_finish) \
  X(cairo_surface_flush) \
  X(cairo_surface_status) \
  X(cairo_svg_surface_create_for_stream) \
  X(cairo_svg_surface_set_document_unit) \
  X(cairo_translate) \
  X(g_object_unref) \
  X(g_type_check_instance_cast) \
  X(g_type_check_instance_is_a) \
  X(pango_cairo_context_set_font_options) \
  X(pango_cairo_font_map_new) \
  X(pango_cairo_font_map_new_for_font_type) \
  X(pango_cairo_show_layout) \
  X(pango_cairo_update_context) \
  X(pango_fc_font_map_get_type) \
  X(pango_fc_font_map_set_config) \
  X(pango_font_description_free) \
  X(pango_font_description_from_string) \
  X(pango_font_description_set_absolute_size) \
  X(pango_font_description_set_weight) \
  X(pango_font_map_create_context) \
  X(pango_layout_get_extents) \
  X(pango_layout_new) \
  X(pango_layout_set_font_description) \
  X(pango_layout_set_text)

struct Api {
#define COGMAP_DRAW_POINTER(name) decltype(&::name) name = nullptr;
  COGMAP_DRAW_FUNCTIONS(COGMAP_DRAW_POINTER)
#undef COGMAP_DRAW_POINTER
};

// The table, loaded once (from any thread; the first caller loads it, the
// others wait). Throws std::runtime_error naming the library or function
// that could not be loaded.
const Api& Load();
extern std::atomic<const Api*> loaded;
inline const Api& Get() {
  const Api* a = loaded.load(std::memory_order_acquire);
  return a ? *a : Load();
}

}  // namespace cogmap::draw::dl
