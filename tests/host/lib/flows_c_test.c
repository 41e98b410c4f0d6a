/* The C ABI's configuration and calibration calls, from C: read a simulated board's whole
   configuration (and an OVERFLOW that says the size needed), lay a change over it and read it
   back, refusals that name the field with nothing sent, a calibration file that agrees with the
   board's static inverse (no warning) and one edited beyond its residual (a warning naming both),
   and a quick calibration on palpa-sim's rig that writes its three files and returns its
   summary. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "c_abi_check.h"
#include "palpa/c/palpa.h"

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

/* Opens a simulated board with DIR/PN-1.json a copy of the test data file `name`; the warnings. */
static int curve_warnings(const char* name, char* dir, char* out, size_t capacity) {
  EXPECT(mkdtemp(dir) != NULL, "mkdtemp");
  char from[600], to[600], text[65536];
  snprintf(from, sizeof from, "%s/%s", PALPA_TEST_DATA_DIR, name);
  snprintf(to, sizeof to, "%s/PN-1.json", dir);
  FILE* in = fopen(from, "rb");
  FILE* copy = fopen(to, "wb");
  EXPECT(in != NULL && copy != NULL, "%s", from);
  if (in == NULL || copy == NULL) return PALPA_STATUS_IO_ERROR;
  fwrite(text, 1, fread(text, 1, sizeof text, in), copy);
  fclose(in);
  fclose(copy);
  setenv("PALPA_CALIBRATION_DIR", dir, 1);
  palpa_device* d = NULL;
  int s = palpa_open("sim:thesis-5finger", &d);
  EXPECT(s == PALPA_OK, "open: %s", palpa_last_error(NULL));
  if (s != PALPA_OK) return s;
  s = palpa_curve_warnings(d, out, capacity, NULL);
  palpa_close(d);
  unsetenv("PALPA_CALIBRATION_DIR");
  return s;
}

static void curves(void) {
  char dir[] = "/tmp/palpa-flows-c-XXXXXX", out[8192];
  int s = curve_warnings("curve_on_board.json", dir, out, sizeof out);
  EXPECT(s == PALPA_OK && strcmp(out, "[]") == 0, "%s: %s", palpa_status_name(s), out);
  char edited[] = "/tmp/palpa-flows-c-XXXXXX";
  s = curve_warnings("curve_off_board.json", edited, out, sizeof out);
  EXPECT(s == PALPA_OK, "%s", palpa_status_name(s));
  char file[600];
  snprintf(file, sizeof file, "\"file\":\"%s/PN-1.json\"", edited);
  EXPECT(strstr(out, file) != NULL, "%s", out);
  EXPECT(strstr(out, "\"finger\":0") != NULL, "%s", out);
  EXPECT(strstr(out, "the board's static inverse for finger 0 (the nominal one)") != NULL, "%s",
         out);
  EXPECT(strstr(out, "\"disagreement\":40.0") != NULL, "%s", out);
  EXPECT(strstr(out, "\"residual\":12.0") != NULL, "%s", out);
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

  /* At the simulator's top speed: what this test holds is the C call and its files, not the rig,
     and palpa-sim judges the host's silence in real time too, so a loaded host keeps its 100 ms. */
  snprintf(options, sizeof options,
           "{\"finger\": 0, \"out\": \"%s\", \"quick\": true, \"compensator\": \"api\","
           " \"sim\": {\"seed\": 3, \"speed\": 10}}",
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
  palpa_device* d = open_board("sim:thesis-5finger");
  if (d == NULL) return 1;
  configuration(d);
  palpa_close(d);
  curves();
  calibration();
  return verdict("flows_c");
}
