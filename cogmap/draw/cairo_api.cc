#include "cogmap/draw/cairo_api.h"

#include <dlfcn.h>

#include <mutex>
#include <stdexcept>
#include <string>

namespace cogmap::draw::dl {

std::atomic<const Api*> loaded{nullptr};

namespace {

// Loaded in dependency order, each global (the later ones and cairo's own
// plug-ins resolve against the earlier ones); never unloaded.
constexpr const char* kLibraries[] = {"libglib-2.0.so.0",    "libgobject-2.0.so.0",    "libfontconfig.so.1",
                                      "libcairo.so.2",       "libpango-1.0.so.0",      "libpangoft2-1.0.so.0",
                                      "libpangocairo-1.0.so.0"};

}  // namespace

const Api& Load() {
  static Api api;
  static std::once_flag once;
  static std::string error;
  std::call_once(once, [] {
    for (const char* lib : kLibraries) {
      if (!dlopen(lib, RTLD_NOW | RTLD_GLOBAL)) {
        const char* e = dlerror();
        error = std::string("cannot load the drawing library ") + lib + ": " + (e ? e : "unknown error") +
                " (Debian: libpangocairo-1.0-0)";
        return;
      }
    }
#define COGMAP_DRAW_RESOLVE(name)                                                           \
  if (error.empty()) {                                                                      \
    void* p = dlsym(RTLD_DEFAULT, #name);                                                   \
    if (p)                                                                                  \
      api.name = reinterpret_cast<decltype(api.name)>(p);                                   \
    else                                                                                    \
      error = std::string("the drawing libraries lack ") + #name + " (too old a version?)"; \
  }
    COGMAP_DRAW_FUNCTIONS(COGMAP_DRAW_RESOLVE)
#undef COGMAP_DRAW_RESOLVE
    if (error.empty()) loaded.store(&api, std::memory_order_release);
  });
  if (!error.empty()) throw std::runtime_error(error);
  return api;
}

}  // namespace cogmap::draw::dl
