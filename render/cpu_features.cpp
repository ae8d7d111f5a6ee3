#include "render/cpu_features.h"

namespace wsd::render {

#if defined(WSD_AVX_DISPATCH)
namespace {

bool cpu_has_avx() {
    __builtin_cpu_init();                  // this runs before main: the CPU model may not be read yet
    return __builtin_cpu_supports("avx");  // the CPU's, and the OS saving its registers
}

bool cpu_has_avx512() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f");  // the OS saving the registers too
}

}  // namespace

bool g_avx_walk = cpu_has_avx();
bool g_avx512_packets = cpu_has_avx512();

bool set_avx_walk(bool on) {
    g_avx_walk = on && cpu_has_avx();
    return g_avx_walk;
}

bool set_avx512_packets(bool on) {
    g_avx512_packets = on && cpu_has_avx512();
    return avx512_packets();
}
#else
bool set_avx_walk(bool) {
    return false;
}
bool set_avx512_packets(bool) {
    return false;
}
#endif

}  // namespace wsd::render
