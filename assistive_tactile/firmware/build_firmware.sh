#!/usr/bin/env bash
# Compiles and links firmware/vest/vest.ino (with the core's Wire library, for the IMU) for an
# ATmega328P (Duemilanove/Uno) with Debian's gcc-avr, avr-libc and arduino-core-avr, without the
# Arduino IDE. Prints the image size.
#   firmware/build_firmware.sh [OUT_DIR]      (exit 0 = the sketch builds)
# Upload (not done here): avrdude -p m328p -c arduino -P /dev/ttyUSB0 -b 57600 -U flash:w:OUT/vest.hex
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
OUT="${1:-/tmp/assistive_vest_fw}"
CORE="${ARDUINO_CORE:-/usr/share/arduino/hardware/arduino/avr}"
command -v avr-g++ >/dev/null || { echo "avr-g++ not installed (apt: gcc-avr avr-libc)"; exit 2; }
[ -f "$CORE/cores/arduino/Arduino.h" ] || { echo "Arduino core not found at $CORE (apt: arduino-core-avr)"; exit 2; }
WIRE="$CORE/libraries/Wire/src"
[ -f "$WIRE/Wire.h" ] || { echo "Wire library not found at $WIRE (apt: arduino-core-avr)"; exit 2; }
mkdir -p "$OUT/core" "$OUT/wire"
FLAGS=(-mmcu=atmega328p -DF_CPU=16000000L -DARDUINO=10807 -DARDUINO_AVR_DUEMILANOVE -DARDUINO_ARCH_AVR
       -Os -ffunction-sections -fdata-sections -Wall -Wextra
       -I"$CORE/cores/arduino" -I"$CORE/variants/standard" -I"$WIRE" -I"$HERE/vest")
objs=()
for src in "$CORE"/cores/arduino/*.c; do
  o="$OUT/core/$(basename "$src").o"; avr-gcc "${FLAGS[@]}" -w -std=gnu11 -c "$src" -o "$o"; objs+=("$o")
done
for src in "$CORE"/cores/arduino/*.cpp; do
  # WString.cpp does not build with Debian's gcc-avr 5.4 (non-constant array size); unused here.
  [ "$(basename "$src")" = WString.cpp ] && continue
  o="$OUT/core/$(basename "$src").o"
  avr-g++ "${FLAGS[@]}" -w -std=gnu++11 -fpermissive -fno-exceptions -fno-threadsafe-statics -c "$src" -o "$o"; objs+=("$o")
done
for src in "$CORE"/cores/arduino/*.S; do
  o="$OUT/core/$(basename "$src").o"; avr-gcc "${FLAGS[@]}" -x assembler-with-cpp -c "$src" -o "$o"; objs+=("$o")
done
# Wire (the IMU's I2C): not ours either, built like the core (-w).
o="$OUT/wire/twi.c.o"; avr-gcc "${FLAGS[@]}" -w -std=gnu11 -c "$WIRE/utility/twi.c" -o "$o"; objs+=("$o")
o="$OUT/wire/Wire.cpp.o"
avr-g++ "${FLAGS[@]}" -w -std=gnu++11 -fpermissive -fno-exceptions -fno-threadsafe-statics -c "$WIRE/Wire.cpp" -o "$o"; objs+=("$o")
# The sketch: as the IDE does, prepend Arduino.h and compile as C++ (warnings are errors here).
{ echo '#include <Arduino.h>'; echo "#line 1 \"$HERE/vest/vest.ino\""; cat "$HERE/vest/vest.ino"; } > "$OUT/vest.ino.cpp"
avr-g++ "${FLAGS[@]}" -Werror -std=gnu++11 -fno-exceptions -fno-threadsafe-statics -c "$OUT/vest.ino.cpp" -o "$OUT/vest.ino.o"
avr-gcc -mmcu=atmega328p -Os -Wl,--gc-sections -o "$OUT/vest.elf" "$OUT/vest.ino.o" "${objs[@]}" -lm
avr-objcopy -O ihex -R .eeprom "$OUT/vest.elf" "$OUT/vest.hex"
avr-size "$OUT/vest.elf"
echo "firmware OK: $OUT/vest.hex"
