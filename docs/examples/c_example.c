/* palpa from C: open a simulated board, set two fingers, drain telemetry without blocking while
   doing other work, read each finger's output in its unit, set several fingers at once without
   waiting, play a scene, E-stop.
   cc c_example.c $(pkg-config --cflags --libs palpa) */
#define _POSIX_C_SOURCE 199309L /* nanosleep */

#include <palpa/c/palpa.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static void Sleep10ms(void) {
  const struct timespec ten_ms = {0, 10 * 1000 * 1000};
  nanosleep(&ten_ms, NULL);
}

int main(int argc, char** argv) {
  palpa_device* board = NULL;
  int status = palpa_open("sim:thesis-5finger", &board);
  if (status != PALPA_OK) {
    fprintf(stderr, "open: %s: %s\n", palpa_status_name(status), palpa_last_error(NULL));
    return 1;
  }
  palpa_info info;
  palpa_get_info(board, &info);
  printf("%s: %u fingers\n", info.config_name, info.finger_count);

  /* Fingers from 0: pneumatic finger 0 to level 2, jamming finger 3 to 1.0 N/mm. */
  status = palpa_set_level(board, 0, 2);
  if (status == PALPA_OK) status = palpa_set_stiffness(board, 3, 1.0);
  if (status != PALPA_OK) {
    fprintf(stderr, "set: %s: %s\n", palpa_status_name(status), palpa_last_error(board));
    palpa_close(board);
    return 1;
  }
  /* A refusal comes back as a named status and a sentence. */
  status = palpa_set_stiffness(board, 0, 1.0);
  printf("N/mm on finger 0: %s (%s)\n", palpa_status_name(status), palpa_last_error(board));
  if (status != PALPA_STATUS_BAD_VALUE) return 1;

  /* The fingers re-home first (about 350 ms), then move. Meanwhile: other work, and a drain of
     whatever telemetry has arrived, never waiting for more (timeout 0). */
  static palpa_sample samples[256];
  palpa_sample last = {0};
  long received = 0;
  for (int i = 0; i < 100; ++i) {
    int n;
    while ((n = palpa_read_samples(board, samples, 256, 0)) > 0) {
      last = samples[n - 1];
      received += n;
    }
    Sleep10ms(); /* the application's own work */
  }
  printf("%ld samples, %llu dropped; finger outputs:", received,
         (unsigned long long)palpa_samples_dropped(board));
  for (int f = 0; f < last.finger_count; ++f)
    printf(" %.3f %s", last.finger_output[f], last.finger_unit[f] == PALPA_UNIT_MM ? "mm" : "N/mm");
  printf("\nline 1 %s; faults: %s\n", (last.status[0] & PALPA_LINE_SAFE) ? "safe" : "driven",
         last.fault_bitmap == 0 ? "none" : "latched");
  const int reached = last.finger_count == info.finger_count && last.finger_output[0] > 0.9;

  /* Several fingers at once without waiting (latest-wins): one frame, applied on one tick; the
     second call replaces the first if the board has not applied it yet. */
  const palpa_request both[] = {{0, PALPA_TARGET_LEVEL, 1}, {1, PALPA_TARGET_LEVEL, 2}};
  const palpa_request again[] = {{0, PALPA_TARGET_LEVEL, 2}, {1, PALPA_TARGET_LEVEL, 1}};
  status = palpa_set_fingers(board, both, 2, 0);
  if (status == PALPA_OK) status = palpa_set_fingers(board, again, 2, 0);
  if (status != PALPA_OK) {
    fprintf(stderr, "set_fingers: %s\n", palpa_last_error(board));
    palpa_close(board);
    return 1;
  }

  /* A scene (docs/scenes.md): fed without waiting, every finger's target in one frame. */
  palpa_scene* scene = NULL;
  /* The scene file: the first argument, or the example's beside this source. */
  char scene_file[1024];
  const char* slash = strrchr(__FILE__, '/');
  snprintf(scene_file, sizeof scene_file, "%.*s/scene_three_cube.json",
           slash ? (int)(slash - __FILE__) : 1, slash ? __FILE__ : ".");
  status = palpa_scene_open(board, argc > 1 ? argv[1] : scene_file, &scene);
  if (status != PALPA_OK) {
    fprintf(stderr, "scene: %s\n", palpa_last_error(board));
    palpa_close(board);
    return 1;
  }
  palpa_finger_render renders[PALPA_MAX_FINGERS];
  int fingers = 0;
  for (int step = 0; step <= 30; ++step) {
    fingers = palpa_scene_feed(scene, step * 0.02, 45 + step, 12, 1.0, renders, PALPA_MAX_FINGERS);
    Sleep10ms();
  }
  for (int f = 0; f < fingers; ++f)
    printf("scene: finger %d target %.3f\n", renders[f].finger, renders[f].target);
  palpa_scene_close(scene);

  palpa_estop(board);
  palpa_close(board);
  return reached && fingers == 3 ? 0 : 2;
}
