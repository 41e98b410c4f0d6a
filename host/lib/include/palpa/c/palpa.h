/* palpa C ABI: opaque handles and status codes; no C++ types cross it. */
#ifndef PALPA_C_PALPA_H_
#define PALPA_C_PALPA_H_

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes: the wire protocol's (docs/protocol.md), shared by every layer. Every call that
   returns an int returns one of these (palpa_read_samples: a count, or a negated code);
   palpa_status_name() gives its stable name ("out_of_range"), palpa_last_error() the sentence. */
#define PALPA_OK 0
#define PALPA_STATUS_NO_SESSION 1         /* no Hello yet in this boot of the board */
#define PALPA_STATUS_UNSUPPORTED 2        /* unknown message type or feature */
#define PALPA_STATUS_BAD_LENGTH 3         /* body shorter or longer than its fields */
#define PALPA_STATUS_OUT_OF_RANGE 4       /* outside a range, a limit or a calibration */
#define PALPA_STATUS_BAD_VALUE 5          /* NaN, a unit meaningless for the finger, bad text */
#define PALPA_STATUS_SEQ_GAP 6            /* (link internal) */
#define PALPA_STATUS_WINDOW_FULL 7        /* (link internal) */
#define PALPA_STATUS_FAULTED 8            /* refused while the board is in its safe state */
#define PALPA_STATUS_CONDITION_PERSISTS 9 /* clear refused: the fault's cause is still present */
#define PALPA_STATUS_CATALOG_MISMATCH 10  /* the board runs other firmware: only flashing */
#define PALPA_STATUS_CRC_ERROR 11
#define PALPA_STATUS_VERSION_ERROR 12
#define PALPA_STATUS_RESERVED_FLAGS 13
#define PALPA_STATUS_OVERFLOW 14
#define PALPA_STATUS_TIMEOUT 15         /* no answer in time */
#define PALPA_STATUS_OUTCOME_UNKNOWN 16 /* the board reset while the command was in flight */
#define PALPA_STATUS_NOT_FOUND 17       /* no such finger, line, device or file */
#define PALPA_STATUS_IO_ERROR 18
#define PALPA_STATUS_UNAVAILABLE 19 /* not possible in the current state */
#define PALPA_STATUS_WRONG_MODE 20
#define PALPA_STATUS_STAGED_INCOMPLETE 21
#define PALPA_STATUS_IMAGE_INVALID 22
#define PALPA_STATUS_ROLLBACK_REFUSED 23
#define PALPA_STATUS_STALE 24
#define PALPA_STATUS_BUSY 25
#define PALPA_STATUS_DISCONNECTED 26     /* the link is gone */
#define PALPA_STATUS_INVALID_ARGUMENT 27 /* a NULL pointer, a negative count or timeout */

/* Line status bits (palpa_sample.status[]): what a line is doing at that tick. */
#define PALPA_LINE_SAFE (1u << 0)         /* holding its safe value */
#define PALPA_LINE_SLEWING (1u << 1)      /* slew limiter active */
#define PALPA_LINE_TRIM_CLAMPED (1u << 2) /* PI trim at its authority */
#define PALPA_LINE_SATURATED (1u << 3)    /* output clamped to the line's limits */
#define PALPA_LINE_OPEN_LOOP (1u << 4)    /* no sensor, or below the regulator's minimum */
#define PALPA_LINE_RAW (1u << 5)          /* its finger is in raw mode (kPa setpoints) */
#define PALPA_LINE_SENSOR_FAULT (1u << 6) /* implausible reading */

/* Fault bits (fault_bitmap): latched until palpa_clear_fault() and their cause gone. */
#define PALPA_FAULT_HOST_SILENCE (1u << 0) /* no host frame within the host timeout */
#define PALPA_FAULT_OVER_LIMIT (1u << 1)   /* a reading beyond a line's limits */
#define PALPA_FAULT_IMPLAUSIBLE_SENSOR (1u << 2)
#define PALPA_FAULT_CONFIG_CRC (1u << 3)
#define PALPA_FAULT_UNEXPECTED_RESET (1u << 4)
#define PALPA_FAULT_LEAK (1u << 5)          /* pressure or vacuum not reached in time */
#define PALPA_FAULT_ESTOP_COMMAND (1u << 6) /* palpa_estop() */
#define PALPA_FAULT_ESTOP_PIN (1u << 7)
#define PALPA_FAULT_PUMP_RUN_TIME (1u << 8)
#define PALPA_FAULT_OUTPUT_WRITE (1u << 9)

/* Finger kinds (palpa_info.finger_kind[]) and the unit of each finger's output. */
#define PALPA_FINGER_PNEUMATIC 0 /* output: deformation in mm */
#define PALPA_FINGER_JAMMING 1   /* output: stiffness in N/mm */
#define PALPA_UNIT_MM 0
#define PALPA_UNIT_N_PER_MM 1

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
  char config_name[25]; /* always NUL-terminated */
  uint8_t line_count;
  uint8_t finger_count;
  uint8_t finger_kind[PALPA_MAX_FINGERS]; /* PALPA_FINGER_PNEUMATIC or PALPA_FINGER_JAMMING */
  uint32_t fault_bitmap;                  /* PALPA_FAULT_* bits, when the device was opened */
} palpa_info;

typedef struct {
  uint64_t board_time_us;
  double host_time_s; /* the host's steady clock (seconds since it started), not wall time */
  uint8_t line_count;
  int32_t setpoint_pa[PALPA_MAX_LINES];
  int32_t measured_pa[PALPA_MAX_LINES];
  uint16_t command_counts[PALPA_MAX_LINES];
  uint8_t status[PALPA_MAX_LINES]; /* PALPA_LINE_* bits */
  uint32_t fault_bitmap;           /* PALPA_FAULT_* bits, latched */
  /* Each finger's output in its unit (finger_unit[]: PALPA_UNIT_MM or PALPA_UNIT_N_PER_MM),
     estimated on the host from its lines' measured pressure (the setpoint where a line has no
     sensor) through the finger's curve: the calibration's, else the nominal one. A static
     estimate: it leaves out the hysteresis the board's compensator works against. */
  uint8_t finger_count;
  double finger_output[PALPA_MAX_FINGERS];
  uint8_t finger_unit[PALPA_MAX_FINGERS];
} palpa_sample;

/* Opens a device URI ("sim:thesis-5finger", "serial:/dev/ttyACM0", "tcp:HOST:PORT",
   "hid:1209:0001", "usb:1209:0001"), or "serve:HOST:PORT[?token=T]": a board behind a running
   `palpa serve` (docs/serve.md), which several programs watch while one controls it. Through
   serve: info, palpa_set_* and palpa_set_fingers (always waiting until applied), palpa_estop
   (anyone's), palpa_clear_fault, palpa_release, palpa_read_samples (every sample, as the server
   sends them 30 times a second; command_counts 0), the configuration calls and
   palpa_last_error/palpa_last_faults work as on a board opened here; fingers from 0, as here.
   The first call that acts on the board takes control, never by force: while another client of
   the server holds it, the call is refused with PALPA_STATUS_BUSY naming the holder; palpa_close
   gives control up and the server releases the board. Recording, calibration, curve warnings and
   scenes are refused with PALPA_STATUS_UNSUPPORTED ("not available through palpa serve").
   On failure *out is NULL and palpa_last_error(NULL) says why, naming the address: a malformed
   one (PALPA_STATUS_INVALID_ARGUMENT), one where nothing listens (PALPA_STATUS_UNAVAILABLE). */
int palpa_open(const char* uri, palpa_device** out);
/* Ends the session (every output safe at once, no fault latched, the board free for another host)
   and frees the device. A process that exits without it leaves the board to its host-silence
   timeout: safe as well, but a fault if fingers were actuated. */
void palpa_close(palpa_device* device);
/* The last error message of this device (or of the last failed open or device-less call, for
   NULL); never NULL. A refusal for latched faults names each, when it latched (board time) and
   what to do. */
const char* palpa_last_error(const palpa_device* device);
/* The latched faults (bits, as in palpa_info.fault_bitmap) the last failed call was refused for;
   0 when it was not refused for faults. */
uint32_t palpa_last_faults(const palpa_device* device);
/* A fault bit's name ("host_silence", "leak", ...); "fault_N" for one this library does not know
   (that text stays valid until the calling thread's next call). */
const char* palpa_fault_name(int bit);
const char* palpa_status_name(int status);

int palpa_get_info(palpa_device* device, palpa_info* info);

/* Setting fingers. Fingers are numbered from 0 here (the command line numbers them from 1).
   Each call returns once the board applied the request (telemetry shows it) or refused it.
   Applied is not yet moved: a finger that leaves its safe state (the first target after opening,
   after palpa_clear_fault or a raw setpoint) first re-homes — vented (pneumatic) or released
   (jamming) for the board's homing dwell, board.home_dwell_ms, 300 ms by default — so a first
   target starts to move about 350 ms after the call returns, then follows the regulator (about
   50 ms to 90 %). A board makes its outputs safe once the host that holds its session has sent
   nothing fresh for its host-silence timeout (100 ms by default): the library keeps the session
   alive while the device is open, and palpa_close() ends it at once. */
int palpa_set_level(palpa_device* device, uint8_t finger, int level);
int palpa_set_normalized(palpa_device* device, uint8_t finger, double value);
int palpa_set_stiffness(palpa_device* device, uint8_t finger,
                        double n_per_mm);                                   /* jamming fingers */
int palpa_set_deformation(palpa_device* device, uint8_t finger, double mm); /* pneumatic fingers */
int palpa_set_pressure(palpa_device* device, uint8_t finger, double kpa);   /* raw mode */
/* Several fingers at once, in one frame (the board applies them on one tick). kind is one of
   PALPA_TARGET_*; value in its unit. Every request is mapped and checked before anything is sent
   (an error names the finger). wait = 0 returns once the frame is sent: the stream is
   latest-wins, so a later call replaces one the board has not applied yet; wait = 1 returns once
   the board applied it (as palpa_set_*). */
#define PALPA_TARGET_LEVEL 0
#define PALPA_TARGET_NORMALIZED 1
#define PALPA_TARGET_STIFFNESS 2   /* N/mm, jamming fingers */
#define PALPA_TARGET_DEFORMATION 3 /* mm, pneumatic fingers */
#define PALPA_TARGET_PRESSURE 4    /* kPa, raw mode */
typedef struct {
  uint8_t finger;
  int kind;
  double value;
} palpa_request;
int palpa_set_fingers(palpa_device* device, const palpa_request* requests, int count, int wait);

int palpa_estop(palpa_device* device);
int palpa_clear_fault(palpa_device* device);
/* Every output safe at once, no fault latched; the session stays open and a later set actuates. */
int palpa_release(palpa_device* device);

/* Telemetry. From palpa_open on, every sample (one per board tick: 1 kHz by default) is queued
   for the device, up to PALPA_SAMPLE_QUEUE_LIMIT; when the queue is full the oldest sample is
   dropped for each new one and counted (palpa_samples_dropped), so a reader that falls behind
   loses its oldest samples, never the newest. */
#define PALPA_SAMPLE_QUEUE_LIMIT 65536

/* Moves up to `capacity` queued samples to `out`, oldest first, and returns how many (or a
   negated status). timeout_ms = 0 never waits: it returns what is queued, possibly 0 — a drain
   for a loop that does other work; timeout_ms > 0 waits up to that long for a first sample. */
int palpa_read_samples(palpa_device* device, palpa_sample* out, int capacity, int timeout_ms);
/* Samples dropped from a full queue since the device was opened. */
uint64_t palpa_samples_dropped(const palpa_device* device);

int palpa_record_start(palpa_device* device, const char* csv_path);
int palpa_record_stop(palpa_device* device);

/* Text results (JSON) are copied NUL-terminated into `out` when their length is below
   `capacity`; else the call returns PALPA_STATUS_OVERFLOW having done its work. *length (when not
   NULL) receives the text's length, without the NUL, either way: call again with a larger buffer
   for a read; keep the size for next time after a calibration. */

/* Configuration, as `palpa config` reads and writes it (docs/configuration.md; lines and fingers
   numbered from 0). palpa_config_read: the board's whole live configuration as JSON.
   palpa_config_apply: a (partial) configuration in the same JSON laid over the live one, checked
   field by field and as the board would (nothing is sent when a check fails: the error names the
   field or section), then sent staged so the board applies all of it or none. Not saved:
   palpa_config_save keeps the live configuration across resets. */
int palpa_config_read(palpa_device* device, char* out, size_t capacity, size_t* length);
int palpa_config_apply(palpa_device* device, const char* json);
int palpa_config_save(palpa_device* device);

/* Calibration files that disagree with the static inverse their finger's board holds by more than
   their fit residual, found on opening: a JSON array of {"finger", "file", "board",
   "disagreement", "at_kpa", "residual", "unit", "message"} (empty when every file agrees). The
   device follows the board's curve for such a finger; the message names both. */
int palpa_curve_warnings(palpa_device* device, char* out, size_t capacity, size_t* length);

/* Calibration of one finger, as `palpa calibrate` does it (docs/calibration.md). `rig` is a rig
   file (its stage and force sensor, beside `device`), or "sim": palpa-sim started for the run
   with a rig on the finger (`device` may be NULL; its errors are then palpa_last_error(NULL)'s).
   `options_json`: {"finger": 0, "out": "DIR"} and optionally "quick", "protocol", "compensator",
   "operators", "target_pct", "max_cycles", "allow_fallback", "resume", "previous", "apply" and
   for "sim" {"sim": {"config", "speed", "unit", "seed", "plant", "effects"}}. Takes minutes
   (seconds of it per sweep point); writes DIR/SERIAL.json, .csv and .html, and on success the
   summary JSON (palpa calibrate --json's: files, compensator, residual, checks) to `out`. */
int palpa_calibrate(palpa_device* device, const char* rig, const char* options_json, char* out,
                    size_t capacity, size_t* length);

/* Scenes (docs/scenes.md): a virtual tissue rendered to the fingers as a hand explores it.
   palpa_scene_open reads a scene file (its tissue, layout, board fingers and rendering rule) for
   `device`, which must stay open while the scene is; errors are palpa_last_error(device)'s.
   palpa_scene_feed renders one input sample — where the hand is on the tissue (mm) and how hard
   it presses (N) — and sends every finger's target in one frame without waiting (latest-wins,
   as palpa_set_fingers with wait = 0); up to `capacity` fingers' renders go to `out` (NULL, 0:
   none). It returns the number of fingers, or a negated status. */
typedef struct palpa_scene palpa_scene;
typedef struct {
  uint8_t finger; /* the board finger, 0-based */
  int touching;   /* 0: released (no contact, or off the tissue) */
  double value;   /* the stiffness under it, in the tissue's unit (N/mm of slope with depth) */
  double depth_mm;
  double u;            /* 0 … 1: where value lies in the scene's range, after its contrast */
  double target;       /* in the finger's unit (finger_unit); 0: released */
  uint8_t finger_unit; /* PALPA_UNIT_MM or PALPA_UNIT_N_PER_MM */
} palpa_finger_render;
int palpa_scene_open(palpa_device* device, const char* scene_path, palpa_scene** out);
int palpa_scene_feed(palpa_scene* scene, double time_s, double x_mm, double y_mm, double force_n,
                     palpa_finger_render* out, int capacity);
void palpa_scene_close(palpa_scene* scene);

/* Prediction: with `on`, each palpa_scene_feed renders where the hand will be after the fingers'
   display delay — from their lines' calibrated chamber models (refused, naming the line, when a
   finger has none: PALPA_STATUS_UNAVAILABLE) — bounded, and not at all when the motion is
   erratic, reversing or stopping; the delay (s) goes to `horizon_s` when not NULL. 0 turns it off.
   Tactile arrays: palpa_scene_feed_tactile renders one frame of the scene's tactile array (its
   input.tactile section: `count` must be its elements), each finger's group averaged and mapped
   by the rule; `values` NULL releases every finger (a stalled stream: the caller decides when).
   Returns as palpa_scene_feed does. */
int palpa_scene_predict(palpa_scene* scene, int on, double* horizon_s);
int palpa_scene_feed_tactile(palpa_scene* scene, const double* values, int count,
                             palpa_finger_render* out, int capacity);

/* Pen tablets and touchpads (evdev): palpa_tablet_open maps the device at `path`
   (/dev/input/eventN) onto the scene's tissue, pressure through the scene's input.tablet form;
   a device that is not a pad is refused naming it and what it lacks (palpa_last_error of the
   scene's device). palpa_tablet_next waits up to timeout_ms for the pad's next report: 1 and the
   sample in `out`, 0 when none came, or a negated status (the device gone). Feed the sample to
   palpa_scene_feed. */
typedef struct palpa_tablet palpa_tablet;
typedef struct {
  double time_s; /* CLOCK_MONOTONIC */
  double x_mm, y_mm, force_n;
} palpa_input;
int palpa_tablet_open(palpa_scene* scene, const char* path, palpa_tablet** out);
int palpa_tablet_next(palpa_tablet* tablet, int timeout_ms, palpa_input* out);
void palpa_tablet_close(palpa_tablet* tablet);

#ifdef __cplusplus
}
#endif

#endif /* PALPA_C_PALPA_H_ */
