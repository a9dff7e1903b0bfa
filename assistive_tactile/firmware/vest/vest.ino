/*
 * Tactile vest firmware (Arduino Duemilanove / Uno, ATmega328 @ 16 MHz).
 *
 * Four vibration motors on PWM pins (through a driver transistor each):
 *   motor 0 left shoulder  -> pin 3  (Timer2)
 *   motor 1 right shoulder -> pin 9  (Timer1)
 *   motor 2 left waist     -> pin 10 (Timer1)
 *   motor 3 right waist    -> pin 11 (Timer2)
 * Serial (hardware UART, USB or XBee): 57600 baud 8N1, the packets of vest_protocol.h (the same
 * file the ROS bridge compiles; here a symlink to include/assistive_tactile/vest_protocol.h).
 *
 * Behaviour (all of it in vest_protocol.h's vest_firmware_* functions, shared with the simulated
 * vest, so what the tests check is what this sketch does):
 *   - bytes are split into COBS frames at 0x00 delimiters; a frame with a bad CRC-32C, a broken
 *     COBS structure, a wrong length or illegal fields is dropped; a CRC-valid frame of another
 *     protocol version is dropped, counted (fw.parser.version_mismatch / peer_version) and
 *     answered with a STATUS in our version, so that peer can report the mismatch;
 *   - a valid COMMAND sets the four PWM duties and is answered with a STATUS packet;
 *   - the last COMMAND's TTL ran out (the PC sets it from the cue's stamps, so a cue ends on
 *     time even when the PC stalls), or no valid COMMAND for 500 ms (VEST_WATCHDOG_MS) -> every
 *     motor off.
 * Motors are off at power-up until the first valid COMMAND.
 */
#include "vest_protocol.h"

static const uint8_t MOTOR_PINS[VEST_NUM_MOTORS] = { 3, 9, 10, 11 };
static const long BAUD = 57600;

static vest_firmware_t fw;

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
      vest_encode(&status, out);
      Serial.write(out, VEST_PACKET_SIZE);
    }
  }
  if (vest_firmware_tick(&fw, millis()))
    applyOutputs();  // watchdog: all motors off
}
