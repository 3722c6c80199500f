"""Write the fuzz regression inputs for issue 19's four output defects (firmware/test/fuzz/regressions/*.bin).

Each file is a fuzz_link.c input (0xFD n type payload: a valid frame; 0xFE k: advance the clock k x 8 ms) that
violated an invariant on the code before the fix; `make fuzz-regress` runs them all (and every crash input the
fuzzer ever found, kept in the same folder). Run: python3 firmware/test/fuzz/make_regressions.py"""
import os
import struct

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "regressions")


def frame(t, payload=b""):
    return bytes([0xFD, len(payload) + 1, t]) + payload


def tick(k):
    return bytes([0xFE, k])


def config_ch(ch, min_us=500, max_us=2500, trim=0, invert=0, lo=-9000, hi=9000, park=0, slew=0):
    return frame(0x20, struct.pack("<BHHhBhhhH", ch, min_us, max_us, trim, invert, lo, hi, park, slew))


ARM, DISARM = frame(0x03), frame(0x04)
CASES = {
    # 1: DISARM, CONFIG_CH 1600..2600 us (and a 5 deg trim), ARM: the stale 1500 us memo was output
    "defect1_config_while_disarmed": ARM + DISARM + config_ch(0, 1600, 2600) + config_ch(1, trim=500) + ARM + tick(3),
    # 2: a SET_PULSES override of 2500 us survived CONFIG_CH max_us 2000
    "defect2_override_narrowed": ARM + frame(0x11, struct.pack("<BBH", 0, 1, 2500)) + config_ch(0, 500, 2000) + tick(2),
    # 3: GAIT drove the joints to the GAIT_SET angles (+60 / -80 deg) after the limits were narrowed to +-10 deg
    "defect3_gait_later_limits": frame(0x40, struct.pack("<BBBBBhh", 8, 1, 1, 1, 0, 6000, -8000))
    + b"".join(config_ch(ch, lo=-1000, hi=1000) for ch in range(8)) + ARM + frame(0x31, b"\x02")
    + frame(0x41, b"\x07") + tick(2) + tick(2) + tick(2),
    # 4: HOLD replaced a SET_PULSES pulse (2300 us) by the angle's (1500 us)
    "defect4_hold_keeps_override": ARM + frame(0x11, struct.pack("<BBH", 0, 1, 2300)) + tick(40) + tick(30),
}

if __name__ == "__main__":
    os.makedirs(HERE, exist_ok=True)
    for name, data in CASES.items():
        with open(os.path.join(HERE, name + ".bin"), "wb") as f:
            f.write(data)
        print(name, len(data), "bytes")
