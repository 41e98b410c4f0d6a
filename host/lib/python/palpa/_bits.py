"""Line status bits (sample["status"][line]) and fault bits (fault_bitmap) in words, as in
palpa.h."""

LINE_STATUS_BITS = {"safe": 1 << 0, "slewing": 1 << 1, "trim_clamped": 1 << 2, "saturated": 1 << 3,
                    "open_loop": 1 << 4, "raw": 1 << 5, "sensor_fault": 1 << 6}
FAULT_BITS = {"host_silence": 1 << 0, "over_limit": 1 << 1, "implausible_sensor": 1 << 2,
              "config_crc": 1 << 3, "unexpected_reset": 1 << 4, "leak": 1 << 5,
              "estop_command": 1 << 6, "estop_pin": 1 << 7, "pump_run_time": 1 << 8,
              "output_write": 1 << 9}


def bit_names(bits, table):
    """The names of the bits set, e.g. bit_names(sample["fault_bitmap"], FAULT_BITS); a bit the
    table does not know (from a newer board) as "bit_N"."""
    names = [name for name, bit in table.items() if bits & bit]
    known = sum(table.values())
    names += [f"bit_{i}" for i in range(32) if bits & ~known & (1 << i)]
    return names

