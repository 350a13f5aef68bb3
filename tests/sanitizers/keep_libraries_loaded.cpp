// Preloaded (LD_PRELOAD) into every process of the ASan test stage (CMakePresets.json
// "asan"): dlclose does nothing. GLFW unloads libGL and Mesa its GL driver (swrast_dri.so)
// before exit; LeakSanitizer then no longer sees the blocks those libraries' globals still
// point to and reports them as leaks of an "<unknown module>", which no suppression can
// name with GCC 12's runtime (a known limitation, google/sanitizers#89). Kept loaded, the
// libraries' memory is reachable again, so nothing needs suppressing and a leak of ours is
// still reported. Built without instrumentation: the shell and Xvfb load it too.
extern "C" int dlclose(void* /*handle*/) { return 0; }
