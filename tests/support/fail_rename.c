/* A test shim (LD_PRELOAD, tests/robustness_policy_test.cpp): rename(2) onto a file whose name is
   NF_TEST_FAIL_RENAME_TO fails with EIO, so a test can make the second output of a command fail
   to be committed after the first one was, deterministically (a full disk or a vanished folder
   would be needed otherwise). Every other rename goes to the C library. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail_target(const char* to) {
  const char* name = getenv("NF_TEST_FAIL_RENAME_TO");
  if (!name || !*name || !to) return 0;
  const char* base = strrchr(to, '/');
  return strcmp(base ? base + 1 : to, name) == 0;
}

int rename(const char* from, const char* to) {
  static int (*real)(const char*, const char*) = NULL;
  if (!real) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  if (fail_target(to)) {
    errno = EIO;
    return -1;
  }
  return real(from, to);
}

int renameat(int fromfd, const char* from, int tofd, const char* to) {
  static int (*real)(int, const char*, int, const char*) = NULL;
  if (!real) real = (int (*)(int, const char*, int, const char*))dlsym(RTLD_NEXT, "renameat");
  if (fail_target(to)) {
    errno = EIO;
    return -1;
  }
  return real(fromfd, from, tofd, to);
}
