"""The data-sheet rows of the IMU presets (:mod:`aaria_pin.core.imu_presets`), original units.

Each row: the quantity as the data sheet names it, its value and unit there, where it is (the
data sheet's table or section), and the model field it sets. The docs' preset table and the
comments of :func:`~aaria_pin.core.imu_presets.imu_model_toml` are made from these rows.
"""

from __future__ import annotations

__all__ = ["DATASHEET_ROWS", "PRESET_ROWS", "PRESET_SOURCES", "PresetRow"]

DATASHEET_ROWS: tuple[tuple[str, float, str], ...] = (
    ("gyro range", 450.0, "+/- deg/s"),
    ("gyro resolution", 0.02, "deg/s per LSB"),
    ("gyro rate noise density", 0.0066, "deg/s/sqrt(Hz)"),
    ("gyro in-run bias stability", 6.25, "deg/h (1 sigma)"),
    ("gyro angle random walk", 0.3, "deg/sqrt(h)"),
    ("accel range", 5.0, "+/- g"),
    ("accel resolution", 0.25, "mg per LSB"),
    ("accel noise density", 0.067, "mg/sqrt(Hz)"),
    ("accel in-run bias stability", 32.0, "ug (1 sigma)"),
    ("accel velocity random walk", 0.023, "m/s/sqrt(h)"),
    ("bandwidth", 330.0, "Hz"),
    ("internal sample rate", 2460.0, "SPS"),
)
"""ADIS16485 data-sheet values in their original units: (name, value, unit) rows."""

_ADIS16485_TABLE = "ADI ADIS16485 data sheet Rev. D, Table 1"
_ADIS16470_TABLE = "ADI ADIS16470 data sheet Rev. C, Table 1"
_ADIS16470_DRIVER = "Linux drivers/iio/imu/adis16475.c (ADIS16470 chip info)"
_BMI_GYRO = "Bosch BST-BMI088-DS000-19 rev 1.9, Table 5"
_BMI_ACCEL = "Bosch BST-BMI088-DS000-19 rev 1.9, Table 4"
_ICM_GYRO = "TDK DS-000347 rev 1.8, Table 1"
_ICM_ACCEL = "TDK DS-000347 rev 1.8, Table 2"
_MPU_GYRO = "InvenSense PS-MPU-6000A-00 rev 3.4, section 6.1 (p. 12)"
_MPU_ACCEL = "InvenSense PS-MPU-6000A-00 rev 3.4, section 6.2 (p. 13)"
_MPU_REGISTERS = "InvenSense RM-MPU-6000A register map, register 26 (CONFIG)"
_ICM_FILTER = "TDK DS-000347 rev 1.8, section 5.5"
_BMI_RATES = "Bosch BST-BMI088-DS000-19 rev 1.9, Table 8"

PresetRow = tuple[str, float, str, str, str]
"""A data-sheet row of a preset: (quantity, value, unit as the data sheet gives it, source, the
field it sets: ``gyro.<name>``, ``accel.<name>`` or a per-IMU field's name)."""

PRESET_ROWS: dict[str, tuple[PresetRow, ...]] = {
    "adis16485": tuple(
        (*row, _ADIS16485_TABLE, field)
        for row, field in zip(
            DATASHEET_ROWS,
            (
                "gyro.range",
                "gyro.lsb",
                "gyro.noise_density",
                "gyro.bias_stability",
                "gyro.random_walk",
                "accel.range",
                "accel.lsb",
                "accel.noise_density",
                "accel.bias_stability",
                "accel.random_walk",
                "bandwidth_hz",
                "internal_rate_hz",
            ),
            strict=True,
        )
    ),
    "adis16470": (
        ("gyro range", 2000.0, "+/- deg/s", _ADIS16470_TABLE, "gyro.range"),
        (
            "gyro resolution, 32-bit output",
            0.1 / 65536,
            "deg/s per LSB",
            _ADIS16470_DRIVER,
            "gyro.lsb",
        ),
        (
            "gyro rate noise density",
            0.008,
            "deg/s/sqrt(Hz)",
            _ADIS16470_TABLE,
            "gyro.noise_density",
        ),
        ("gyro in-run bias stability", 8.0, "deg/h", _ADIS16470_TABLE, "gyro.bias_stability"),
        ("accel range", 40.0, "+/- g", _ADIS16470_TABLE, "accel.range"),
        (
            "accel resolution, 32-bit output",
            1.25 / 65536,
            "mg per LSB",
            _ADIS16470_DRIVER,
            "accel.lsb",
        ),
        (
            "accel noise density",
            0.1,
            "mg/sqrt(Hz)",
            f"{_ADIS16470_TABLE} (via a secondary copy)",
            "accel.noise_density",
        ),
        ("accel in-run bias stability", 13.0, "ug", _ADIS16470_TABLE, "accel.bias_stability"),
        ("internal sample rate", 2000.0, "SPS", _ADIS16470_DRIVER, "internal_rate_hz"),
        ("Bartlett filter -3 dB, FILT_CTRL = 0", 720.0, "Hz", _ADIS16470_DRIVER, "bandwidth_hz"),
    ),
    "bmi088": (
        ("gyro range (reset)", 2000.0, "+/- deg/s", _BMI_GYRO, "gyro.range"),
        ("gyro resolution", 1.0 / 16.384, "deg/s per LSB", _BMI_GYRO, "gyro.lsb"),
        ("gyro rate noise density", 0.014, "deg/s/sqrt(Hz)", _BMI_GYRO, "gyro.noise_density"),
        ("gyro zero-rate offset", 1.0, "+/- deg/s", _BMI_GYRO, "gyro.bias_offset"),
        ("gyro sensitivity tolerance", 1.0, "+/- %", _BMI_GYRO, "gyro.scale_error"),
        ("gyro non-linearity", 0.05, "+/- %FS", _BMI_GYRO, "gyro.nonlinearity"),
        ("gyro cross-axis sensitivity", 1.0, "%", _BMI_GYRO, "gyro.cross_axis"),
        ("gyro g-sensitivity (max)", 0.1, "deg/s/g", _BMI_GYRO, "gyro.g_sensitivity"),
        ("accel range (reset)", 6.0, "+/- g", _BMI_ACCEL, "accel.range"),
        ("accel resolution", 1000.0 / 5460.0, "mg per LSB", _BMI_ACCEL, "accel.lsb"),
        (
            "accel noise density x, y (z: 190)",
            160.0,
            "ug/sqrt(Hz)",
            _BMI_ACCEL,
            "accel.noise_density",
        ),
        ("accel zero-g offset", 20.0, "mg", _BMI_ACCEL, "accel.bias_offset"),
        ("accel non-linearity", 0.5, "%FS", _BMI_ACCEL, "accel.nonlinearity"),
        ("accel cross-axis sensitivity", 0.5, "%", _BMI_ACCEL, "accel.cross_axis"),
        ("accel alignment error to package", 0.5, "deg", _BMI_ACCEL, "accel.misalignment"),
        ("accel output data rate (reset)", 100.0, "Hz", _BMI_RATES, "internal_rate_hz"),
        ("accel bandwidth, ODR 100 Hz normal", 40.0, "Hz", _BMI_RATES, "bandwidth_hz"),
    ),
    "icm42688p": (
        ("gyro range (default)", 2000.0, "+/- deg/s", _ICM_GYRO, "gyro.range"),
        (
            "gyro resolution, 19-bit FIFO word",
            2000.0 / 2**18,
            "deg/s per LSB",
            _ICM_GYRO,
            "gyro.lsb",
        ),
        ("gyro rate noise density", 0.0028, "deg/s/sqrt(Hz)", _ICM_GYRO, "gyro.noise_density"),
        (
            "gyro initial zero-rate offset (board level)",
            0.5,
            "+/- deg/s",
            _ICM_GYRO,
            "gyro.bias_offset",
        ),
        ("gyro sensitivity tolerance", 0.5, "+/- %", _ICM_GYRO, "gyro.scale_error"),
        ("gyro non-linearity", 0.1, "+/- %", _ICM_GYRO, "gyro.nonlinearity"),
        ("gyro cross-axis sensitivity", 1.25, "+/- %", _ICM_GYRO, "gyro.cross_axis"),
        ("accel range (default)", 16.0, "+/- g", _ICM_ACCEL, "accel.range"),
        (
            "accel resolution, 18-bit FIFO word",
            1000.0 / 8192.0,
            "mg per LSB",
            _ICM_ACCEL,
            "accel.lsb",
        ),
        (
            "accel noise density x, y (z: 70)",
            65.0,
            "ug/sqrt(Hz)",
            _ICM_ACCEL,
            "accel.noise_density",
        ),
        (
            "accel initial zero-g offset (board level)",
            20.0,
            "+/- mg",
            _ICM_ACCEL,
            "accel.bias_offset",
        ),
        ("accel sensitivity tolerance", 0.5, "+/- %", _ICM_ACCEL, "accel.scale_error"),
        ("accel non-linearity", 0.1, "+/- %", _ICM_ACCEL, "accel.nonlinearity"),
        ("accel cross-axis sensitivity", 1.0, "+/- %", _ICM_ACCEL, "accel.cross_axis"),
        ("output data rate modelled", 1000.0, "Hz", _ICM_FILTER, "internal_rate_hz"),
        ("UI filter -3 dB, 1st order at ODR 1 kHz", 498.0, "Hz", _ICM_FILTER, "bandwidth_hz"),
    ),
    "mpu6050": (
        ("gyro range (FS_SEL = 0)", 250.0, "+/- deg/s", _MPU_GYRO, "gyro.range"),
        ("gyro resolution", 1.0 / 131.0, "deg/s per LSB", _MPU_GYRO, "gyro.lsb"),
        ("gyro rate noise density", 0.005, "deg/s/sqrt(Hz)", _MPU_GYRO, "gyro.noise_density"),
        ("gyro initial ZRO tolerance", 20.0, "+/- deg/s", _MPU_GYRO, "gyro.bias_offset"),
        ("gyro sensitivity scale factor tolerance", 3.0, "+/- %", _MPU_GYRO, "gyro.scale_error"),
        ("gyro non-linearity", 0.2, "%", _MPU_GYRO, "gyro.nonlinearity"),
        ("gyro cross-axis sensitivity", 2.0, "+/- %", _MPU_GYRO, "gyro.cross_axis"),
        ("gyro linear acceleration sensitivity", 0.1, "deg/s/g", _MPU_GYRO, "gyro.g_sensitivity"),
        ("accel range (AFS_SEL = 0)", 2.0, "+/- g", _MPU_ACCEL, "accel.range"),
        ("accel resolution", 1000.0 / 16384.0, "mg per LSB", _MPU_ACCEL, "accel.lsb"),
        ("accel power spectral density", 400.0, "ug/sqrt(Hz)", _MPU_ACCEL, "accel.noise_density"),
        ("accel zero-g output x, y (z: 80)", 50.0, "+/- mg", _MPU_ACCEL, "accel.bias_offset"),
        ("accel initial calibration tolerance", 3.0, "+/- %", _MPU_ACCEL, "accel.scale_error"),
        ("accel non-linearity", 0.5, "%", _MPU_ACCEL, "accel.nonlinearity"),
        ("accel cross-axis sensitivity", 2.0, "+/- %", _MPU_ACCEL, "accel.cross_axis"),
        ("gyro output rate, DLPF_CFG = 0", 8000.0, "Hz", _MPU_REGISTERS, "internal_rate_hz"),
        ("gyro DLPF bandwidth, DLPF_CFG = 0", 256.0, "Hz", _MPU_REGISTERS, "bandwidth_hz"),
    ),
}
"""Each preset's data-sheet rows, original units (the docs' table and the template's comments)."""

PRESET_SOURCES: dict[str, str] = {
    "adis16485": "Analog Devices ADIS16485 data sheet Rev. D (the Aaria paper's IMU)",
    "adis16470": "Analog Devices ADIS16470 data sheet Rev. C; Linux adis16475.c",
    "bmi088": "Bosch Sensortec BMI088 data sheet BST-BMI088-DS000-19 rev 1.9 (2024)",
    "icm42688p": "TDK InvenSense ICM-42688-P data sheet DS-000347 rev 1.8 (2023)",
    "mpu6050": "InvenSense MPU-6000/MPU-6050 product specification PS-MPU-6000A-00 rev 3.4",
}
"""The data sheet of each preset."""
