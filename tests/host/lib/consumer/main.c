/* A tiny application: open a simulated board through the installed library and print it. */
#include <stdio.h>

#include <palpa/c/palpa.h>

int main(void) {
  palpa_device* board = NULL;
  int status = palpa_open("sim:thesis-pneumatic-3", &board);
  if (status != PALPA_OK) {
    fprintf(stderr, "open: %s: %s\n", palpa_status_name(status), palpa_last_error(NULL));
    return 1;
  }
  palpa_info info;
  palpa_get_info(board, &info);
  printf("%s: %u fingers\n", info.config_name, info.finger_count);
  status = palpa_set_level(board, 0, 1);
  palpa_close(board);
  return status == PALPA_OK && info.finger_count == 3 ? 0 : 2;
}
