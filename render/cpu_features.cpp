#include "render/cpu_features.h"

namespace wsd::render {

#if defined(WSD_AVX_DISPATCH)
namespace {

bool cpu_has_avx() {
    __builtin_cpu_init();                  // this runs before main: the CPU model may not be read yet
    return __builtin_cpu_supports("avx");  // the CPU's, and the OS saving its registers
}

}  // namespace

bool g_avx_walk = cpu_has_avx();

bool set_avx_walk(bool on) {
    g_avx_walk = on && cpu_has_avx();
    return g_avx_walk;
}
#else
bool set_avx_walk(bool) {
    return false;
}
#endif

}  // namespace wsd::render
