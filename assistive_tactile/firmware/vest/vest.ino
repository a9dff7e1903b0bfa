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
 * Serial (hardware UART, USB or XBee): 57600 baud 8N1, the packets of vest_protocol.h (the same
 * file the ROS bridge compiles; here a symlink to include/assistive_tactile/vest_protocol.h).
 *
 * Behaviour (all of it in vest_protocol.h's vest_firmware_* functions, shared with the simulated
 * vest, so what the tests check is what this sketch does):
 *   - bytes are split into COBS frames at 0x00 delimiters; a frame with a bad CRC-32C, a broken
 *     COBS structure, a wrong length or illegal fields is dropped; a CRC-valid frame of another
 *     protocol version is dropped, counted (fw.parser.version_mismatch / peer_version) and
 *     answered with a STATUS in our version, so that peer can report the mismatch;
 *   - a valid COMMAND sets the four PWM duties and its pulse pattern (protocol version 4) and
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
 *   - RANGE and BUTTONS only to a bridge that spoke version 3 or 4, in its version.
 * Motors are off at power-up until the first valid COMMAND.
 */
#include "vest_protocol.h"

static const uint8_t MOTOR_PINS[VEST_NUM_MOTORS] = { 3, 9, 10, 11 };
static const uint8_t TRIG_PIN = 4, ECHO_PIN = 2, BUTTON_A_PIN = 5, BUTTON_B_PIN = 6;
static const long BAUD = 57600;

static vest_firmware_t fw;

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

template <typename T>
static void sendPacket(const T* p, void (*encode)(const T*, uint8_t, uint8_t*), uint8_t size)
{
  uint8_t out[VEST_PACKET_SIZE];
  encode(p, vest_firmware_sensor_version(&fw), out);  // the bridge's version (3 or 4)
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
}
