# Cross toolchain for the Cortex-M images (Debian's gcc-arm-none-eabi, picolibc).
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_OBJCOPY arm-none-eabi-objcopy)
set(CMAKE_SIZE arm-none-eabi-size)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)

# Cortex-M4F with its single-precision FPU; float only (no soft double), no exceptions, no RTTI.
set(PALPA_CPU_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
set(CMAKE_C_FLAGS_INIT "${PALPA_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_ASM_FLAGS_INIT "${PALPA_CPU_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${PALPA_CPU_FLAGS} -ffunction-sections -fdata-sections -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit -Wdouble-promotion -fsingle-precision-constant")
# picolibc's speed-optimised build: its memcpy/memset move words, the size-optimised ones bytes
# (a configuration change copies ≈ 6 KB several times: 2.5 times the instructions), for 480 B.
set(CMAKE_EXE_LINKER_FLAGS_INIT "${PALPA_CPU_FLAGS} -nostartfiles -Wl,--gc-sections --specs=picolibc.specs --picolibc-buildtype=release")
