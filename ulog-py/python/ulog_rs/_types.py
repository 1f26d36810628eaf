"""pyulog's basic types: what ``ULog`` reads and ``write_ulog`` writes."""

import numpy as np

# Per basic type: the struct code, the size and the numpy type pyulog gives it
# (pyulog reads `bool` and `char` as int8).
_TYPES = {
    "int8_t": ("b", 1, np.int8),
    "uint8_t": ("B", 1, np.uint8),
    "int16_t": ("h", 2, np.int16),
    "uint16_t": ("H", 2, np.uint16),
    "int32_t": ("i", 4, np.int32),
    "uint32_t": ("I", 4, np.uint32),
    "int64_t": ("q", 8, np.int64),
    "uint64_t": ("Q", 8, np.uint64),
    "float": ("f", 4, np.float32),
    "double": ("d", 8, np.float64),
    "bool": ("?", 1, np.int8),
    "char": ("c", 1, np.int8),
}
