/* Preloaded into the sanitized test processes (scripts/run_sanitized_tests.sh): dlclose keeps every
   library loaded. The OpenCL and OpenGL drivers unload modules (PoCL's compiled kernels, Mesa's
   driver) before exit; LeakSanitizer then sees their allocations as "<unknown module>" and cannot
   match them to the driver suppressions of lsan.supp. Nothing else changes: a module that stays
   mapped is never used again. */
int dlclose(void* handle);

int dlclose(void* handle) {
  (void)handle;
  return 0;
}
