/* palpa C ABI: opaque handles and status codes; no C++ types cross it. */
#ifndef PALPA_C_PALPA_H_
#define PALPA_C_PALPA_H_

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes are the wire protocol's (docs/protocol.md): 0 is success. */
#define PALPA_OK 0

typedef struct palpa_device palpa_device;

#define PALPA_MAX_LINES 8
#define PALPA_MAX_FINGERS 8

typedef struct {
  uint32_t board_id;
  uint8_t firmware_major, firmware_minor, firmware_patch;
  uint8_t board_kind; /* 0 sim, 1 mps2-an386, 2 stm32f4, 3 linux */
  uint32_t catalog_hash;
  int catalog_matches; /* 0: only flashing is possible */
  int plant_simulated;
  float time_scale;
  char config_name[25];
  uint8_t line_count;
  uint8_t finger_count;
  uint8_t finger_kind[PALPA_MAX_FINGERS]; /* 0 pneumatic, 1 jamming */
  uint32_t fault_bitmap;
} palpa_info;

typedef struct {
  uint64_t board_time_us;
  double host_time_s;
  uint8_t line_count;
  int32_t setpoint_pa[PALPA_MAX_LINES];
  int32_t measured_pa[PALPA_MAX_LINES];
  uint16_t command_counts[PALPA_MAX_LINES];
  uint8_t status[PALPA_MAX_LINES];
  uint32_t fault_bitmap;
} palpa_sample;

/* Opens a device URI ("sim:thesis-5finger", "serial:/dev/ttyACM0", "tcp:HOST:PORT",
   "hid:1209:0001", "usb:1209:0001"). On failure *out is NULL and palpa_last_error(NULL) says why.
 */
int palpa_open(const char* uri, palpa_device** out);
void palpa_close(palpa_device* device);
/* The last error message of this device (or of the last failed open, for NULL); never NULL. */
const char* palpa_last_error(const palpa_device* device);
const char* palpa_status_name(int status);

int palpa_get_info(palpa_device* device, palpa_info* info);

/* Fingers are 0-based. Each call waits until the board applied it or refused it. */
int palpa_set_level(palpa_device* device, uint8_t finger, int level);
int palpa_set_normalized(palpa_device* device, uint8_t finger, double value);
int palpa_set_stiffness(palpa_device* device, uint8_t finger,
                        double n_per_mm);                                   /* jamming fingers */
int palpa_set_deformation(palpa_device* device, uint8_t finger, double mm); /* pneumatic fingers */
int palpa_set_pressure(palpa_device* device, uint8_t finger, double kpa);   /* raw mode */
int palpa_estop(palpa_device* device);
int palpa_clear_fault(palpa_device* device);

/* Telemetry: samples (one per board tick) queued since the last call, at most `capacity`;
   waits up to timeout_ms for the first. Returns the count, or a negative status. */
int palpa_read_samples(palpa_device* device, palpa_sample* out, int capacity, int timeout_ms);

int palpa_record_start(palpa_device* device, const char* csv_path);
int palpa_record_stop(palpa_device* device);

#ifdef __cplusplus
}
#endif

#endif /* PALPA_C_PALPA_H_ */
