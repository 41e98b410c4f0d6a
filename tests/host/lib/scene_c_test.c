/* Scenes and several-finger requests through the C ABI, from C, on palpa-sim: a scene file opened
   for a device, samples fed without waiting with each finger's render returned, a lifted hand
   releasing every finger, several fingers set in one call (waiting and not), refusals that say
   why, and telemetry drained without waiting. */
#include <stdio.h>
#include <string.h>

#include "c_abi_check.h"
#include "palpa/c/palpa.h"

static void scene(palpa_device* d) {
  palpa_scene* s = NULL;
  int status = palpa_scene_open(d, PALPA_DOCS_DIR "/examples/scene_three_cube.json", &s);
  EXPECT(status == PALPA_OK, "%s", palpa_last_error(d));
  if (s == NULL) return;
  palpa_finger_render r[8];
  /* Finger 0 on cube B, the others on the block. */
  int n = palpa_scene_feed(s, 0, 60, 12, 1.0, r, 8);
  EXPECT(n == 3, "%d: %s", n, palpa_last_error(d));
  EXPECT(r[0].finger == 0 && r[2].finger == 2, "fingers %d %d", r[0].finger, r[2].finger);
  EXPECT(r[0].touching && r[0].u > 0.99, "u %g", r[0].u);
  EXPECT(r[0].target > 1.0 && r[0].finger_unit == PALPA_UNIT_MM, "target %g", r[0].target);
  EXPECT(r[1].target < r[0].target, "%g %g", r[1].target, r[0].target);
  /* Lifted: every finger released. */
  n = palpa_scene_feed(s, 0.01, 60, 12, 0, r, 8);
  EXPECT(n == 3, "%d", n);
  for (int k = 0; k < 3; ++k) EXPECT(!r[k].touching && r[k].target == 0, "finger %d", k);
  /* No room for renders is fine: the targets still go. */
  EXPECT(palpa_scene_feed(s, 0.02, 30, 15, 1, NULL, 0) == 3, "%s", palpa_last_error(d));
  palpa_scene_close(s);
  status = palpa_scene_open(d, "/nonexistent/scene.json", &s);
  EXPECT(status == PALPA_STATUS_NOT_FOUND && s == NULL, "%s", palpa_status_name(status));
  EXPECT(strstr(palpa_last_error(d), "/nonexistent/scene.json") != NULL, "%s", palpa_last_error(d));
}

/* Tactile frames grouped per finger, the release of a stalled stream, prediction refused where
   the fingers' delay is not calibrated, and a device that is not a pen tablet. */
static void inputs(palpa_device* d) {
  palpa_scene* s = NULL;
  int status = palpa_scene_open(d, PALPA_DOCS_DIR "/examples/scene_inputs.json", &s);
  EXPECT(status == PALPA_OK, "%s", palpa_last_error(d));
  if (s == NULL) return;
  palpa_finger_render r[8];
  /* Rows of a 3 x 3 array: means 40, 20 and 0 of the 0 … 40 kPa range. */
  const double frame[9] = {36, 40, 44, 10, 20, 30, 0, 0, 0};
  int n = palpa_scene_feed_tactile(s, frame, 9, r, 8);
  EXPECT(n == 3, "%d: %s", n, palpa_last_error(d));
  EXPECT(r[0].touching && r[0].u > 0.999 && r[0].value == 40, "u %g value %g", r[0].u, r[0].value);
  EXPECT(r[1].u > 0.499 && r[1].u < 0.501, "u %g", r[1].u);
  EXPECT(r[2].target == 0, "target %g", r[2].target);
  n = palpa_scene_feed_tactile(s, NULL, 0, r, 8);
  EXPECT(n == 3 && !r[0].touching && r[0].target == 0, "%d", n);
  n = palpa_scene_feed_tactile(s, frame, 8, r, 8);
  EXPECT(n == -PALPA_STATUS_INVALID_ARGUMENT, "%d", n);
  EXPECT(strstr(palpa_last_error(d), "8 values, the scene's array has 9") != NULL, "%s",
         palpa_last_error(d));
  double horizon = -1;
  status = palpa_scene_predict(s, 1, &horizon);
  EXPECT(status == PALPA_STATUS_UNAVAILABLE, "%s", palpa_status_name(status));
  EXPECT(strstr(palpa_last_error(d), "line 1 has no chamber model") != NULL, "%s",
         palpa_last_error(d));
  EXPECT(palpa_scene_predict(s, 0, NULL) == PALPA_OK, "%s", palpa_last_error(d));
  palpa_tablet* t = NULL;
  status = palpa_tablet_open(s, "/dev/null", &t);
  EXPECT(status != PALPA_OK && t == NULL, "%s", palpa_status_name(status));
  EXPECT(strstr(palpa_last_error(d), "/dev/null: not an input event device") != NULL, "%s",
         palpa_last_error(d));
  palpa_scene_close(s);
}

static void several(palpa_device* d) {
  const palpa_request up[3] = {{0, PALPA_TARGET_DEFORMATION, 1.0},
                               {1, PALPA_TARGET_LEVEL, 1},
                               {2, PALPA_TARGET_NORMALIZED, 0.5}};
  int status = palpa_set_fingers(d, up, 3, 1);
  EXPECT(status == PALPA_OK, "%s", palpa_last_error(d));
  status = palpa_set_fingers(d, up, 3, 0);
  EXPECT(status == PALPA_OK, "%s", palpa_last_error(d));
  const palpa_request bad[2] = {{0, PALPA_TARGET_DEFORMATION, 1.0}, {1, PALPA_TARGET_STIFFNESS, 1}};
  status = palpa_set_fingers(d, bad, 2, 0);
  EXPECT(status == PALPA_STATUS_BAD_VALUE, "%s", palpa_status_name(status));
  EXPECT(strstr(palpa_last_error(d), "finger 1: N/mm means nothing") != NULL, "%s",
         palpa_last_error(d));
  const palpa_request odd = {0, 9, 1.0};
  status = palpa_set_fingers(d, &odd, 1, 0);
  EXPECT(status == PALPA_STATUS_INVALID_ARGUMENT, "%s", palpa_status_name(status));
  EXPECT(strstr(palpa_last_error(d), "requests[0].kind 9") != NULL, "%s", palpa_last_error(d));
  palpa_sample samples[64];
  EXPECT(palpa_read_samples(d, samples, 64, 0) >= 0, "%s", palpa_last_error(d));
}

int main(void) {
  palpa_device* d = open_board("sim:thesis-pneumatic-3");
  if (d == NULL) return 1;
  scene(d);
  inputs(d);
  several(d);
  palpa_close(d);
  return verdict("scene_c");
}
