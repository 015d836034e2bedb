#include "core/log.h"

#include <atomic>

namespace nf::log {
namespace {
std::atomic<Level> g_level{Level::info};
}
Level level() { return g_level.load(); }
void set_level(Level l) { g_level.store(l); }
}  // namespace nf::log
