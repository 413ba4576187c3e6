"""Bitwise comparison of two EXR files written by isg: every byte, except the value of the
`capDate` header attribute (the time of writing, added when the input has no DateTime)."""


def masked(path, names=(b"capDate",)):
    """The file's bytes with the values of the named header attributes zeroed (single part)."""
    with open(path, "rb") as f:
        b = bytearray(f.read())
    if b[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    i = 8
    while b[i] != 0:
        name_end = b.index(0, i)
        type_end = b.index(0, name_end + 1)
        size = int.from_bytes(b[type_end + 1:type_end + 5], "little")
        value = type_end + 5
        if bytes(b[i:name_end]) in names:
            b[value:value + size] = bytes(size)
        i = value + size
    return bytes(b)


def same(a, b):
    return masked(a) == masked(b)
