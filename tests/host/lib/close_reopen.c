/* A C application's sessions, through the C ABI: open, set, close, reopen and set; a second open
   while one is held is told busy; a refusal for a latched fault names it, when and what to do.
     palpa_close_reopen URI        (exit 0: all as expected; 1: the first thing that was not) */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "palpa/c/palpa.h"

#define FAULT_ESTOP_COMMAND 6
#define STATUS_FAULTED 8
#define STATUS_BUSY 25

static int Fail(const char* what, int status, const char* error) {
  fprintf(stderr, "close_reopen: %s (status %s: %s)\n", what, palpa_status_name(status), error);
  return 1;
}

static void Pause(int ms) {
  const struct timespec t = {ms / 1000, (long)(ms % 1000) * 1000000L};
  nanosleep(&t, NULL);
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: palpa_close_reopen URI\n");
    return 2;
  }
  const char* uri = argv[1];
  palpa_device* first = NULL;
  int s = palpa_open(uri, &first);
  if (s != PALPA_OK) return Fail("open", s, palpa_last_error(NULL));
  s = palpa_set_level(first, 0, 2);
  if (s != PALPA_OK) return Fail("set", s, palpa_last_error(first));

  palpa_device* second = NULL; /* the board is held: told so, not left waiting */
  s = palpa_open(uri, &second);
  if (s != STATUS_BUSY || second != NULL ||
      strstr(palpa_last_error(NULL), "busy: another host holds the board") == NULL)
    return Fail("a second open while the first is held is not busy", s, palpa_last_error(NULL));

  palpa_close(first); /* outputs safe at once, no fault */
  Pause(200);         /* twice the board's host-silence timeout */

  palpa_device* again = NULL;
  s = palpa_open(uri, &again);
  if (s != PALPA_OK) return Fail("reopen", s, palpa_last_error(NULL));
  palpa_info info;
  palpa_get_info(again, &info);
  if (info.fault_bitmap != 0) return Fail("a closed session left a fault", s, "");
  s = palpa_set_level(again, 0, 2);
  if (s != PALPA_OK) return Fail("set after reopening", s, palpa_last_error(again));

  /* A refusal for a latched fault: named, with when it latched and what to do. */
  palpa_estop(again);
  s = palpa_set_level(again, 0, 1);
  const char* why = palpa_last_error(again);
  if (s != STATUS_FAULTED || palpa_last_faults(again) != (1u << FAULT_ESTOP_COMMAND) ||
      strstr(why, "estop_command, latched at board time") == NULL ||
      strstr(why, "Clear the fault") == NULL ||
      strcmp(palpa_fault_name(FAULT_ESTOP_COMMAND), "estop_command") != 0)
    return Fail("a set refused for an E-stop does not say so", s, why);
  s = palpa_clear_fault(again);
  if (s != PALPA_OK) return Fail("clear", s, palpa_last_error(again));
  s = palpa_set_level(again, 0, 1);
  if (s != PALPA_OK) return Fail("set after clearing", s, palpa_last_error(again));
  palpa_close(again);
  printf("close_reopen: ok\n");
  return 0;
}
