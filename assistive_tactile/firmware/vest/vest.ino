/*
 * Tactile vest firmware (Arduino Duemilanove / Uno, ATmega328 @ 16 MHz).
 *
 * Four vibration motors on PWM pins (through a driver transistor each):
 *   motor 0 left shoulder  -> pin 3  (Timer2)
 *   motor 1 right shoulder -> pin 9  (Timer1)
 *   motor 2 left waist     -> pin 10 (Timer1)
 *   motor 3 right waist    -> pin 11 (Timer2)
 * Forward ultrasonic ranger (HC-SR04 class, 5 V): TRIG -> pin 4, ECHO -> pin 2 (INT0; a 10 k
 * pull-down keeps a missing sensor's line low, so it reads "sensor missing", never "no echo").
 * Push buttons A -> pin 5, B -> pin 6, to ground (internal pull-ups: low = down).
 * IMU: MPU-6050 on a GY-521 breakout, I2C at 400 kHz, address 0x68 (AD0 open): VCC -> 5 V (the
 * GY-521's own regulator makes the chip's 3.3 V), GND -> GND, SDA -> A4, SCL -> A5, INT unused
 * (polled). Keep its wires short (400 kHz). Mounted on the torso x forward, y left, z up
 * (REP-103); the PC takes the vertical from the accelerometer, so the mounting's tilt does not
 * matter to the body's yaw rate.
 * Serial (hardware UART, USB or XBee): 57600 baud 8N1, the packets of vest_protocol.h (the same
 * file the ROS bridge compiles; here a symlink to include/assistive_tactile/vest_protocol.h).
 * Vest -> PC at 57600 baud (5.76 kB/s): IMU 26 bytes x 50 Hz = 1.3 kB/s, STATUS 21 x 20 Hz, RANGE
 * 14 x 20 Hz, BUTTONS 15 x 1 Hz: 2.0 kB/s, 35 % of the link, so the 64-byte TX buffer drains
 * between loops and Serial.write seldom waits.
 *
 * Behaviour (all of it in vest_protocol.h's vest_firmware_* functions, shared with the simulated
 * vest, so what the tests check is what this sketch does):
 *   - bytes are split into COBS frames at 0x00 delimiters; a frame with a bad CRC-32C, a broken
 *     COBS structure, a wrong length or illegal fields is dropped; a CRC-valid frame of another
 *     protocol version is dropped, counted (fw.parser.version_mismatch / peer_version) and
 *     answered with a STATUS in our version, so that peer can report the mismatch;
 *   - a valid COMMAND sets the four PWM duties and its pulse pattern (protocol version 4 on) and
 *     is answered with a STATUS packet (what the outputs do now, the pattern playing);
 *   - the pattern is timed here, on millis(), not by the PC: the duties are driven only while
 *     vest_pattern_on() says so; a COMMAND carrying the pattern that plays continues its phase
 *     (the PC re-sends at 20 Hz), another pattern starts at phase 0; so serial jitter and lost
 *     packets never change a pulse's length or the number of pulses;
 *   - the last COMMAND's TTL ran out (the PC sets it from the cue's stamps, so a cue ends on
 *     time even when the PC stalls), or no valid COMMAND for 500 ms (VEST_WATCHDOG_MS) -> every
 *     motor off, whatever the pattern.
 *   - a COMMAND of version 2 or 3 (an old bridge, no pattern bytes) is obeyed too, steady, and
 *     answered in its version;
 *   - every 50 ms the ranger is triggered; the echo line is timed by an interrupt (no busy wait:
 *     the motors' TTL keeps its millisecond), each ping is classified (echo / no echo / no sensor)
 *     and the median of the last 3 pings goes out in a RANGE packet;
 *   - the buttons are debounced; presses (short, long) and changes go out in BUTTONS packets, with
 *     a heartbeat once a second;
 *   - every 5 ms (VEST_IMU_SAMPLE_MS) the IMU is read: gyro +-500 deg/s and accel +-4 g (a torso's
 *     turns and a walk's jolts fit), behind the sensor's 42 Hz low-pass filter (keeps the motors'
 *     buzz and anything above the 100 Hz Nyquist limit out of the 200 Hz samples); the mean of
 *     each 20 ms goes out in an IMU packet, SENSOR_MISSING when no sample of it could be read. A
 *     sensor that does not answer is configured again at most once a second (plugged in later,
 *     or power-glitched), and the I2C waits time out after 3 ms: the bus never stalls the loop
 *     that times the motors for longer than that;
 *   - RANGE and BUTTONS only to a bridge that spoke version 3, 4 or 5, in its version; IMU only to
 *     a version-5 bridge.
 * Motors are off at power-up until the first valid COMMAND.
 */
#include <Wire.h>
#include "vest_protocol.h"

static const uint8_t MOTOR_PINS[VEST_NUM_MOTORS] = { 3, 9, 10, 11 };
static const uint8_t TRIG_PIN = 4, ECHO_PIN = 2, BUTTON_A_PIN = 5, BUTTON_B_PIN = 6;
static const long BAUD = 57600;

static vest_firmware_t fw;

// MPU-6050 (its register map).
static const uint8_t MPU_ADDR = 0x68, MPU_WHO = 0x68;
static const uint8_t MPU_SMPLRT_DIV = 0x19, MPU_CONFIG = 0x1A, MPU_GYRO_CONFIG = 0x1B, MPU_ACCEL_CONFIG = 0x1C;
static const uint8_t MPU_ACCEL_XOUT_H = 0x3B, MPU_PWR_MGMT_1 = 0x6B, MPU_WHO_AM_I = 0x75;
static const uint8_t MPU_AWAKE_PLL = 0x01;  // PWR_MGMT_1: awake, clocked by the X gyro's PLL
static const uint16_t IMU_RETRY_MS = 1000;
static const uint8_t IMU_SETTLE_SAMPLES = 10;  // 50 ms after waking: the gyro starts in 30 ms
static const float GYRO_MRAD_PER_LSB = 1000.0f * (float)M_PI / 180.0f / 65.5f;  // +-500 deg/s
static const float ACCEL_MM_PER_LSB = 9806.65f / 8192.0f;                      // +-4 g

static uint8_t imu_up = 0;          // configured and answering
static uint8_t imu_skip = 0;        // readings still discarded after waking the sensor
static uint32_t imu_config_ms = 0;  // the last configuration attempt
static uint32_t imu_sample_ms = 0;  // the 5 ms grid of the readings

// Echo line timing, written by the interrupt.
static volatile uint8_t echo_rose = 0, echo_fell = 0;
static volatile uint32_t echo_rise_us = 0, echo_fall_us = 0;
static uint32_t last_ping_ms = 0;
static uint8_t pinging = 0;

static void onEcho()
{
  const uint32_t t = micros();
  if (digitalRead(ECHO_PIN))
  {
    echo_rose = 1;
    echo_rise_us = t;
  }
  else if (echo_rose && !echo_fell)
  {
    echo_fell = 1;
    echo_fall_us = t;
  }
}

static void trigger()
{
  noInterrupts();
  echo_rose = echo_fell = 0;
  interrupts();
  digitalWrite(TRIG_PIN, HIGH);
  delayMicroseconds(10);
  digitalWrite(TRIG_PIN, LOW);
}

static uint8_t mpuWrite(uint8_t reg, uint8_t value)
{
  Wire.beginTransmission(MPU_ADDR);
  Wire.write(reg);
  Wire.write(value);
  return Wire.endTransmission() == 0;
}

// Reads n registers from reg on (repeated start); 1 when all n came.
static uint8_t mpuRead(uint8_t reg, uint8_t* out, uint8_t n)
{
  Wire.beginTransmission(MPU_ADDR);
  Wire.write(reg);
  if (Wire.endTransmission(false) != 0 || Wire.requestFrom(MPU_ADDR, n) != n)
    return 0;
  for (uint8_t i = 0; i < n; ++i)
    out[i] = (uint8_t)Wire.read();
  return 1;
}

// Wakes and configures the MPU-6050; imu_up = 1 when it is one and took every setting.
static void imuConfigure(uint32_t now)
{
  uint8_t who = 0, pwr = 0;
  imu_config_ms = now;
  imu_up = mpuRead(MPU_WHO_AM_I, &who, 1) && who == MPU_WHO && mpuRead(MPU_PWR_MGMT_1, &pwr, 1);
  if (!imu_up)
    return;  // nothing written to a missing sensor or another chip
  const uint8_t asleep = pwr != MPU_AWAKE_PLL;  // 0x40 after its power-up
  imu_up = mpuWrite(MPU_PWR_MGMT_1, MPU_AWAKE_PLL)  // the PLL: steadier than its 8 MHz RC clock
           && mpuWrite(MPU_CONFIG, 3)               // DLPF 44 Hz accel / 42 Hz gyro
           && mpuWrite(MPU_GYRO_CONFIG, 0x08)       // +-500 deg/s, 65.5 LSB per deg/s
           && mpuWrite(MPU_ACCEL_CONFIG, 0x08)      // +-4 g, 8192 LSB per g
           && mpuWrite(MPU_SMPLRT_DIV, 4);          // 1 kHz / (1 + 4) = 200 Hz, one per reading
  imu_skip = imu_up && asleep ? IMU_SETTLE_SAMPLES : 0;
}

// raw * per_lsb, rounded half away from zero, saturated to +-32767.
static int16_t scaled(int16_t raw, float per_lsb)
{
  const float v = (float)raw * per_lsb;
  return vest_sat16((int32_t)(v >= 0.0f ? v + 0.5f : v - 0.5f));
}

// One reading: gyro in mrad/s, accel in mm/s^2. 0 when there is no sample (sensor not up, I2C
// error, just woken).
static uint8_t imuSample(int16_t* gyro, int16_t* accel)
{
  uint8_t b[14];  // accel x, y, z, temperature, gyro x, y, z: int16, high byte first
  if (!imu_up)
    return 0;
  if (!mpuRead(MPU_ACCEL_XOUT_H, b, sizeof(b)))
  {
    imu_up = 0;  // unplugged, or the bus glitched: configure again (loop(), at most once a second)
    return 0;
  }
  if (imu_skip > 0)
  {
    imu_skip--;  // the gyro's start-up and the filter's transient (and zeros before the first sample)
    return 0;
  }
  int16_t raw[7];
  for (uint8_t i = 0; i < 7; ++i)
    raw[i] = (int16_t)((uint16_t)b[2 * i] << 8 | b[2 * i + 1]);
  if (raw[0] == 0 && raw[1] == 0 && raw[2] == 0)
  {
    imu_up = 0;  // gravity never reads 0: the sensor reset (power glitch), asleep, registers at 0
    return 0;
  }
  for (uint8_t i = 0; i < 3; ++i)
  {
    accel[i] = scaled(raw[i], ACCEL_MM_PER_LSB);
    gyro[i] = scaled(raw[4 + i], GYRO_MRAD_PER_LSB);
  }
  return 1;
}

template <typename T>
static void sendPacket(const T* p, void (*encode)(const T*, uint8_t, uint8_t*), uint8_t size)
{
  uint8_t out[VEST_MAX_PACKET_SIZE];
  encode(p, vest_firmware_sensor_version(&fw), out);  // the bridge's version (3, 4 or 5)
  Serial.write(out, size);
}

static void applyOutputs()
{
  for (uint8_t i = 0; i < VEST_NUM_MOTORS; ++i)
    analogWrite(MOTOR_PINS[i], fw.duty[i]);
}

void setup()
{
  for (uint8_t i = 0; i < VEST_NUM_MOTORS; ++i)
  {
    pinMode(MOTOR_PINS[i], OUTPUT);
    digitalWrite(MOTOR_PINS[i], LOW);
  }
  pinMode(TRIG_PIN, OUTPUT);
  digitalWrite(TRIG_PIN, LOW);
  pinMode(ECHO_PIN, INPUT);
  pinMode(BUTTON_A_PIN, INPUT_PULLUP);
  pinMode(BUTTON_B_PIN, INPUT_PULLUP);
  attachInterrupt(digitalPinToInterrupt(ECHO_PIN), onEcho, CHANGE);
  Serial.begin(BAUD);
  Wire.begin();
  Wire.setClock(400000);
  Wire.setWireTimeout(3000, true);  // a hung bus: give up after 3 ms and reset the TWI unit
  imuConfigure(millis());
  imu_sample_ms = millis();
  vest_firmware_init(&fw, millis());
}

void loop()
{
  while (Serial.available() > 0)
  {
    const uint8_t byte = (uint8_t)Serial.read();
    vest_packet_t status;
    const int r = vest_firmware_feed(&fw, byte, millis(), &status);
    if (r != VEST_FEED_NONE)
    {
      if (r == VEST_FEED_APPLIED)
        applyOutputs();  // else: a peer of another protocol version, told ours by the STATUS
      uint8_t out[VEST_PACKET_SIZE];
      const uint8_t n = vest_encode_version(&status, fw.reply_version, out);  // the COMMAND's version
      Serial.write(out, n);
    }
  }
  const uint32_t now = millis();
  if (vest_firmware_tick(&fw, now))
    applyOutputs();  // a pulse began or ended, or TTL / watchdog: all motors off

  // Ranger: classify the last ping, then trigger the next one (every VEST_PING_PERIOD_MS).
  if ((uint32_t)(now - last_ping_ms) >= VEST_PING_PERIOD_MS)
  {
    if (pinging)
    {
      noInterrupts();
      const uint8_t rose = echo_rose, fell = echo_fell;
      const uint32_t width = echo_fall_us - echo_rise_us;
      interrupts();
      uint16_t mm;
      const uint8_t ping = vest_classify_ping(rose, fell, width, &mm);
      vest_range_t range;
      if (vest_firmware_range(&fw, ping, mm, &range))
        sendPacket(&range, vest_encode_range_version, VEST_RANGE_PACKET_SIZE);
    }
    last_ping_ms = now;
    trigger();
    pinging = 1;
  }

  vest_buttons_t buttons;
  if (vest_firmware_buttons(&fw, digitalRead(BUTTON_A_PIN) == LOW, digitalRead(BUTTON_B_PIN) == LOW, now, &buttons))
    sendPacket(&buttons, vest_encode_buttons_version, VEST_BUTTONS_PACKET_SIZE);

  // IMU: a reading every VEST_IMU_SAMPLE_MS on a fixed grid (4 to a 20 ms window), an IMU packet
  // when vest_firmware_imu closes a window.
  if ((uint32_t)(now - imu_sample_ms) >= VEST_IMU_SAMPLE_MS)
  {
    imu_sample_ms += VEST_IMU_SAMPLE_MS;
    if ((uint32_t)(now - imu_sample_ms) >= VEST_IMU_SAMPLE_MS)
      imu_sample_ms = now;  // fell behind: no burst of catch-up readings
    if (!imu_up && (uint32_t)(now - imu_config_ms) >= IMU_RETRY_MS)
      imuConfigure(now);
    int16_t gyro[3] = { 0, 0, 0 }, accel[3] = { 0, 0, 0 };
    const uint8_t ok = imuSample(gyro, accel);
    vest_imu_t imu;
    if (vest_firmware_imu(&fw, ok, gyro, accel, now, &imu))
      sendPacket(&imu, vest_encode_imu_version, VEST_IMU_PACKET_SIZE);
  }
}
