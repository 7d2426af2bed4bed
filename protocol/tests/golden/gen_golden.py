#!/usr/bin/env python3
"""Golden frames of payload format 3, computed independently of the Rust encoder.

Run from anywhere, Python 3 only (no packages):

    python3 protocol/tests/golden/gen_golden.py

It prints one Rust `const` per vector, as pasted into the tests of protocol/src/frame.rs
(`mod tests`). Nothing here imports or runs the crate: the payload layout is written from the
format description (docs/protocol.md, protocol/src/message.rs's doc), and CRC-16/IBM-3740,
COBS, the XOR with 's' and SipHash-2-4 are written out below and checked against their
published check values before anything is printed.

Payload format 3 (docs/protocol.md revision 3.0):
    byte 0    header 0b010r_nnnn: 010 = format 3, r = 1 if a ray follows, nnnn = hops 1..=12
    2 / hop   reading, tag << 4 | pref (pref nibble 0 = none, sector + 1 otherwise)
    ray       sector << 4 | sectors, robots, sum u16 LE (sum of the readings),
              sum_sq u24 LE (sum of their squares), votes[sectors]
    payload <= 25 bytes
Frame: 'ss' + (COBS(payload + check) XOR 's') + 'ss'; check = CRC-16/IBM-3740 LE (plain) or
the first 4 bytes of the little-endian SipHash-2-4 output (keyed).
"""

S = 0x73
PAYLOAD_BUDGET = 25
KEYED_PAYLOAD_MAX = 23
FRAME_MAX = 32

RIGHT, LEFT = 0, 1


def crc16_ibm_3740(data):
    """CRC-16/IBM-3740 (CCITT-FALSE): poly 0x1021, init 0xFFFF, no reflection, no xorout."""
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def cobs(data):
    """Consistent Overhead Byte Stuffing, no trailing zero."""
    out = bytearray([0])
    code_at, code = 0, 1
    for b in data:
        if b == 0:
            out[code_at] = code
            code_at, code = len(out), 1
            out.append(0)
        else:
            out.append(b)
            code += 1
            if code == 0xFF:
                out[code_at] = code
                code_at, code = len(out), 1
                out.append(0)
    out[code_at] = code
    return bytes(out)


def _rotl(x, b):
    return ((x << b) | (x >> (64 - b))) & 0xFFFFFFFFFFFFFFFF


def siphash24(key, msg):
    """SipHash-2-4 (Aumasson and Bernstein, 2012), 64-bit output as an integer."""
    mask = 0xFFFFFFFFFFFFFFFF
    k0 = int.from_bytes(key[:8], "little")
    k1 = int.from_bytes(key[8:], "little")
    v = [
        k0 ^ 0x736F6D6570736575,
        k1 ^ 0x646F72616E646F6D,
        k0 ^ 0x6C7967656E657261,
        k1 ^ 0x7465646279746573,
    ]

    def rnd():
        v[0] = (v[0] + v[1]) & mask
        v[1] = _rotl(v[1], 13) ^ v[0]
        v[0] = _rotl(v[0], 32)
        v[2] = (v[2] + v[3]) & mask
        v[3] = _rotl(v[3], 16) ^ v[2]
        v[0] = (v[0] + v[3]) & mask
        v[3] = _rotl(v[3], 21) ^ v[0]
        v[2] = (v[2] + v[1]) & mask
        v[1] = _rotl(v[1], 17) ^ v[2]
        v[2] = _rotl(v[2], 32)

    n = len(msg)
    tail = msg[n - n % 8 :] + bytes(7 - n % 8) + bytes([n & 0xFF])
    blocks = msg[: n - n % 8] + tail
    for i in range(0, len(blocks), 8):
        m = int.from_bytes(blocks[i : i + 8], "little")
        v[3] ^= m
        rnd()
        rnd()
        v[0] ^= m
    v[2] ^= 0xFF
    for _ in range(4):
        rnd()
    return v[0] ^ v[1] ^ v[2] ^ v[3]


# Published check values: CRC-16/IBM-3740 of "123456789" is 0x29B1 (the CRC catalogue), and
# the SipHash paper's Appendix A vector (key 00..0f, message 00..0e) is 0xa129ca6149be45e5.
assert crc16_ibm_3740(b"123456789") == 0x29B1
assert siphash24(bytes(range(16)), bytes(range(15))) == 0xA129CA6149BE45E5
assert cobs(b"\x00") == b"\x01\x01"
assert cobs(b"\x11\x22\x00\x33") == b"\x03\x11\x22\x02\x33"

GOLDEN_KEY = bytes(range(16))  # "000102030405060708090a0b0c0d0e0f"


def hop(reading, pref=None, tag=0):
    """A hop: (reading, tag, pref); pref None or a sector 0..=7."""
    return (reading, tag, pref)


def ray(sector, sectors, robots, total, total_sq, votes):
    assert 2 <= sectors <= 8 and sector < sectors and robots >= 1
    assert len(votes) == sectors and all(0 <= v <= robots for v in votes)
    # Sums that `robots` readings in 0..=255 can have (docs/protocol.md §1.2).
    assert total <= 255 * robots and total_sq <= 255 * total
    assert total * total <= robots * total_sq
    return (sector, sectors, robots, total, total_sq, votes)


def payload(hops, r=None):
    assert 1 <= len(hops) <= 12
    out = bytearray([0x40 | (0x10 if r else 0) | len(hops)])
    for reading, tag, pref in hops:
        out += bytes([reading, tag << 4 | (0 if pref is None else pref + 1)])
    if r:
        sector, sectors, robots, total, total_sq, votes = r
        out += bytes([sector << 4 | sectors, robots])
        out += total.to_bytes(2, "little") + total_sq.to_bytes(3, "little")
        out += bytes(votes)
    assert len(out) <= PAYLOAD_BUDGET
    return bytes(out)


def frame(p, key=None):
    check = (
        siphash24(key, p).to_bytes(8, "little")[:4]
        if key
        else crc16_ibm_3740(p).to_bytes(2, "little")
    )
    body = bytes(b ^ S for b in cobs(p + check))
    assert S not in body
    f = b"ss" + body + b"ss"
    assert len(f) <= FRAME_MAX
    return f


# The messages of protocol/src/frame.rs's tests.
ONE_HOP = [hop(1)]
FOUR_HOPS = [hop(1, RIGHT), hop(0, LEFT), hop(0, LEFT), hop(0)]
S_BYTES = [hop(S), hop(S)]
# Pattern 1100, a wave from robot 0 to robot 3 as robot 3 sends it.
TAGGED_FOUR = [hop(1, RIGHT, 0), hop(1, RIGHT, 1), hop(0, LEFT, 2), hop(0, LEFT, 3)]
WIDEST_TAGGED = hop(0xFF, 7, 15)
WIDEST = hop(0xFF, 7, 0)
# The ray of RAY_FOUR: the LEFT side of a robot with K = 2, 4 robots reading 200, 200, 30, 30
# (sum 460, sum of squares 81800: mean 115.0, variance 7225.0), two votes each way.
RAY_LEFT_K2 = ray(LEFT, 2, 4, 460, 81800, [2, 2])
# A 7-sector ray (14 bytes): sector 6, 200 robots, sum 0x7373 (two 's' bytes), sum of squares
# 0x700473 (one more), votes summing to 200.
RAY_K7 = ray(6, 7, 200, 0x7373, 0x700473, [10, 20, 30, 40, 50, 0, 50])

VECTORS = [
    ("GOLDEN_ONE_HOP", payload(ONE_HOP), None),
    ("GOLDEN_FOUR_HOPS", payload(FOUR_HOPS), None),
    ("GOLDEN_S_BYTES", payload(S_BYTES), None),
    ("GOLDEN_TAGGED_FOUR", payload(TAGGED_FOUR), None),
    ("GOLDEN_TAGGED_TWELVE", payload([WIDEST_TAGGED] * 12), None),
    ("GOLDEN_RAY_FOUR", payload(TAGGED_FOUR, RAY_LEFT_K2), None),
    # 5 hops + a 7-sector ray: 1 + 10 + 14 = 25 bytes, the whole budget.
    ("GOLDEN_RAY_LARGEST", payload([WIDEST_TAGGED] * 5, RAY_K7), None),
    ("GOLDEN_KEYED_ONE_HOP", payload(ONE_HOP), GOLDEN_KEY),
    ("GOLDEN_KEYED_FOUR_HOPS", payload(FOUR_HOPS), GOLDEN_KEY),
    ("GOLDEN_KEYED_S_BYTES", payload(S_BYTES), GOLDEN_KEY),
    ("GOLDEN_KEYED_TAGGED_FOUR", payload(TAGGED_FOUR), GOLDEN_KEY),
    ("GOLDEN_KEYED_TAGGED_ELEVEN", payload([WIDEST_TAGGED] * 11), GOLDEN_KEY),
    ("GOLDEN_KEYED_ELEVEN", payload([WIDEST] * 11), GOLDEN_KEY),
    ("GOLDEN_KEYED_RAY_FOUR", payload(TAGGED_FOUR, RAY_LEFT_K2), GOLDEN_KEY),
    # 4 hops + a 7-sector ray: 1 + 8 + 14 = 23 bytes, the keyed budget.
    ("GOLDEN_KEYED_RAY_LARGEST", payload([WIDEST_TAGGED] * 4, RAY_K7), GOLDEN_KEY),
]


def rust(f):
    """A Rust byte string: the delimiters as `ss`, every body byte escaped."""
    return 'b"ss' + "".join("\\x%02x" % x for x in f[2:-2]) + 'ss"'


def main():
    for name, p, key in VECTORS:
        if key:
            assert len(p) <= KEYED_PAYLOAD_MAX
        f = frame(p, key)
        print("// payload %s (%d bytes), frame %d bytes" % (p.hex(" "), len(p), len(f)))
        print("const %s: &[u8] = %s;" % (name, rust(f)))


if __name__ == "__main__":
    main()
