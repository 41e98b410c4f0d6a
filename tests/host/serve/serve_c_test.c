/* The C ABI through a running palpa serve (serve:HOST:PORT, argv[1]), as remote_test.py runs it
   in front of palpa-sim: a malformed address and one where nothing listens refused naming it;
   info; a set that moves finger 0 (seen in a second handle's samples), a finger the board lacks
   named as the caller numbers it; the second handle refused busy while the first controls; a call
   the server does not offer refused as unsupported; the configuration applied and read; the
   watcher's E-stop refusing the controller's next set for its fault; clear, release, close. */
#include <stdio.h>
#include <string.h>

#include "c_abi_check.h"
#include "palpa/c/palpa.h"

/* Reads `d`'s samples until finger `f`'s output is above (`above`) or below `mm`, for up to
   `seconds` of samples at 1 kHz; the last output seen. */
static double wait_output(palpa_device* d, int f, double mm, int above, double seconds) {
  static palpa_sample batch[256];
  double last = -1;
  for (int waited = 0; waited < (int)(seconds * 1000);) {
    const int n = palpa_read_samples(d, batch, 256, 100);
    if (n < 0) return last;
    if (n == 0) waited += 100;
    for (int k = 0; k < n; ++k, ++waited) {
      last = batch[k].finger_output[f];
      if (above ? last > mm : last < mm) return last;
    }
  }
  return last;
}

static void refused_addresses(void) {
  palpa_device* d = NULL;
  int s = palpa_open("serve:127.0.0.1", &d);
  EXPECT(s == PALPA_STATUS_INVALID_ARGUMENT && d == NULL, "%s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(NULL), "serve:127.0.0.1: expected serve:HOST:PORT") != NULL, "%s",
         palpa_last_error(NULL));
  printf("ok  a malformed address: %s\n", palpa_last_error(NULL));
  s = palpa_open("serve:127.0.0.1:1", &d);
  EXPECT(s == PALPA_STATUS_UNAVAILABLE && d == NULL, "%s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(NULL), "serve:127.0.0.1:1: nothing listens there") != NULL, "%s",
         palpa_last_error(NULL));
  printf("ok  nothing listening: %s\n", palpa_last_error(NULL));
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: serve_c_test serve:HOST:PORT\n");
    return 2;
  }
  refused_addresses();
  palpa_device* controller = open_board(argv[1]);
  palpa_device* watcher = open_board(argv[1]);
  if (controller == NULL || watcher == NULL) return verdict("serve_c");

  palpa_info info;
  int s = palpa_get_info(controller, &info);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  EXPECT(strcmp(info.config_name, "thesis-5finger") == 0 && info.finger_count == 5 &&
             info.finger_kind[3] == PALPA_FINGER_JAMMING && info.line_count > 0 &&
             info.plant_simulated && info.catalog_matches,
         "%s, %d fingers", info.config_name, info.finger_count);
  printf("ok  info through the server: %s, %d fingers, %d lines, firmware %d.%d.%d\n",
         info.config_name, info.finger_count, info.line_count, info.firmware_major,
         info.firmware_minor, info.firmware_patch);

  s = palpa_set_level(controller, 7, 1);
  EXPECT(s == PALPA_STATUS_NOT_FOUND, "%s", palpa_status_name(s));
  EXPECT(strstr(palpa_last_error(controller),
                "finger 7 does not exist (this board has fingers 0 to 4)") != NULL,
         "%s", palpa_last_error(controller));
  /* The server's own refusal, numbered as the caller numbers: finger 3 is jamming (N/mm). */
  s = palpa_set_deformation(controller, 3, 1.0);
  EXPECT(s != PALPA_OK && strstr(palpa_last_error(controller), "finger 3") != NULL, "%s: %s",
         palpa_status_name(s), palpa_last_error(controller));
  printf("ok  a deformation for jamming finger 3 refused (%s): %s\n", palpa_status_name(s),
         palpa_last_error(controller));
  s = palpa_set_level(controller, 0, 2);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  const double moved = wait_output(watcher, 0, 0.5, 1, 3);
  EXPECT(moved > 0.5, "finger 0 at %.3f mm in the watcher's samples", moved);
  printf("ok  set finger 0 to level 2: %.2f mm in the watcher's samples\n", moved);

  s = palpa_set_level(watcher, 1, 1);
  EXPECT(s == PALPA_STATUS_BUSY, "%s: %s", palpa_status_name(s), palpa_last_error(watcher));
  printf("ok  the second handle's set refused (%s): %s\n", palpa_status_name(s),
         palpa_last_error(watcher));
  s = palpa_record_start(controller, "/dev/null");
  EXPECT(s == PALPA_STATUS_UNSUPPORTED &&
             strstr(palpa_last_error(controller), "not available through palpa serve") != NULL,
         "%s: %s", palpa_status_name(s), palpa_last_error(controller));
  printf("ok  %s\n", palpa_last_error(controller));
  char config[65536];
  s = palpa_config_apply(controller, "{\"board\": {\"host_timeout_us\": 150000}}");
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  s = palpa_config_read(watcher, config, sizeof config, NULL);
  EXPECT(s == PALPA_OK && strstr(config, "\"host_timeout_us\":150000") != NULL, "%s: %.200s",
         palpa_status_name(s), config);
  s = palpa_config_apply(controller, "{\"board\": {\"host_timeout_us\": 100000}}");
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  printf("ok  the configuration applied by the controller, read by the watcher\n");

  s = palpa_estop(watcher);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(watcher));
  s = palpa_set_level(controller, 0, 1);
  EXPECT(s == PALPA_STATUS_FAULTED && (palpa_last_faults(controller) & PALPA_FAULT_ESTOP_COMMAND),
         "%s: %s", palpa_status_name(s), palpa_last_error(controller));
  EXPECT(
      palpa_get_info(watcher, &info) == PALPA_OK && (info.fault_bitmap & PALPA_FAULT_ESTOP_COMMAND),
      "faults 0x%x", info.fault_bitmap);
  printf("ok  the watcher's E-stop: the controller's set refused (%s)\n", palpa_status_name(s));

  s = palpa_clear_fault(controller);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  s = palpa_set_level(controller, 0, 2);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  EXPECT(wait_output(watcher, 0, 0.5, 1, 3) > 0.5, "finger 0 after clearing");
  s = palpa_release(controller);
  EXPECT(s == PALPA_OK, "%s", palpa_last_error(controller));
  const double released = wait_output(watcher, 0, 0.1, 0, 3);
  EXPECT(released < 0.1, "finger 0 at %.3f mm after the release", released);
  printf("ok  cleared, set again, released: finger 0 back to %.2f mm\n", released);
  palpa_close(watcher);
  palpa_close(controller);
  return verdict("serve_c");
}
