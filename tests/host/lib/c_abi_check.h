/* The C ABI tests' shared frame: EXPECT counts a failure and says where and why (the run goes on,
   so one run shows every failure), a simulated board opened or the run ended saying why, and the
   verdict as the exit status. */
#pragma once

#include <stdio.h>

#include "palpa/c/palpa.h"

static int failures = 0;

#define EXPECT(cond, ...)                                        \
  do {                                                           \
    if (!(cond)) {                                               \
      fprintf(stderr, "%s:%d: %s: ", __FILE__, __LINE__, #cond); \
      fprintf(stderr, __VA_ARGS__);                              \
      fprintf(stderr, "\n");                                     \
      ++failures;                                                \
    }                                                            \
  } while (0)

/* The board at `uri` (a sim: URI), or NULL having said why. */
static palpa_device* open_board(const char* uri) {
  palpa_device* d = NULL;
  if (palpa_open(uri, &d) != PALPA_OK) {
    fprintf(stderr, "open %s: %s\n", uri, palpa_last_error(NULL));
    return NULL;
  }
  return d;
}

/* "NAME: ok" or "NAME: FAILED", and the exit status that goes with it. */
static int verdict(const char* name) {
  printf("%s: %s\n", name, failures == 0 ? "ok" : "FAILED");
  return failures == 0 ? 0 : 1;
}
