/* The C ABI's configuration and calibration calls, from C: read a simulated board's whole
   configuration (and an OVERFLOW that says the size needed), lay a change over it and read it
   back, refusals that name the field with nothing sent, and a quick calibration on palpa-sim's
   rig that writes its three files and returns its summary. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

static int exists(const char* path) {
  struct stat st;
  return stat(path, &st) == 0;
}

static void configuration(palpa_device* d) {
  size_t length = 0;
  char small[8];
  int s = palpa_config_read(d, small, sizeof small, &length);
  EXPECT(s == PALPA_STATUS_OVERFLOW, "status %s", palpa_status_name(s));
  EXPECT(length > 1000, "length %zu", length);
  char* text = malloc(length + 1);
  s = palpa_config_read(d, text, length + 1, &length);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(d));
  EXPECT(strstr(text, "\"host_timeout_us\":100000") != NULL, "%.200s", text);
  free(text);

  s = palpa_config_apply(d, "{\"board\": {\"host_timeout_us\": 150000}}");
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(d));
  char out[65536];
  s = palpa_config_read(d, out, sizeof out, NULL);
  EXPECT(s == PALPA_OK && strstr(out, "\"host_timeout_us\":150000") != NULL, "%.200s", out);

  /* Refused before anything is sent, naming the field; the live configuration unchanged. */
  s = palpa_config_apply(d, "{\"board\": {\"host_timeout\": 1}}");
  EXPECT(s == PALPA_STATUS_INVALID_ARGUMENT, "status %s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(d), "host_timeout") != NULL, "%s", palpa_last_error(d));
  s = palpa_config_apply(d, "{\"board\": ");
  EXPECT(s == PALPA_STATUS_INVALID_ARGUMENT, "status %s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(d), "nothing was sent") != NULL, "%s", palpa_last_error(d));
  s = palpa_config_read(d, out, sizeof out, NULL);
  EXPECT(s == PALPA_OK && strstr(out, "\"host_timeout_us\":150000") != NULL, "%.200s", out);
}

static void calibration(void) {
  char dir[] = "/tmp/palpa-flows-c-XXXXXX";
  EXPECT(mkdtemp(dir) != NULL, "mkdtemp");
  char options[512], summary[65536];
  size_t length = 0;

  int s = palpa_calibrate(NULL, "sim", "{\"finger\": 0}", summary, sizeof summary, &length);
  EXPECT(s == PALPA_STATUS_INVALID_ARGUMENT, "status %s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(NULL), "out") != NULL, "%s", palpa_last_error(NULL));
  s = palpa_calibrate(NULL, "lab.json", "{\"finger\": 0, \"out\": \"/tmp\"}", summary,
                      sizeof summary, &length);
  EXPECT(s == PALPA_STATUS_INVALID_ARGUMENT, "status %s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(NULL), "open device") != NULL, "%s", palpa_last_error(NULL));

  /* Half palpa calibrate's default speed: the board's 100 ms host-silence timeout is then 50 ms
     of real time, room for a host sharing loaded cores with the simulator. */
  snprintf(options, sizeof options,
           "{\"finger\": 0, \"out\": \"%s\", \"quick\": true, \"compensator\": \"api\","
           " \"sim\": {\"seed\": 3, \"speed\": 2}}",
           dir);
  s = palpa_calibrate(NULL, "sim", options, summary, sizeof summary, &length);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(NULL));
  EXPECT(strstr(summary, "\"calibrated\":\"PN-1\"") != NULL, "%s", summary);
  EXPECT(strstr(summary, "\"compensator\":\"api(8)\"") != NULL, "%s", summary);
  EXPECT(strstr(summary, "\"finger\":0") != NULL, "%s", summary);
  EXPECT(length == strlen(summary), "length %zu", length);
  const char* files[] = {"PN-1.json", "PN-1.csv", "PN-1.html"};
  for (int i = 0; i < 3; ++i) {
    char path[600];
    snprintf(path, sizeof path, "%s/%s", dir, files[i]);
    EXPECT(exists(path), "%s", path);
  }
}

int main(void) {
  palpa_device* d = NULL;
  if (palpa_open("sim:thesis-5finger", &d) != PALPA_OK) {
    fprintf(stderr, "open: %s\n", palpa_last_error(NULL));
    return 1;
  }
  configuration(d);
  palpa_close(d);
  calibration();
  printf("%s\n", failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
