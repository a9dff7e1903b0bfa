/* Compiled as C99: vest_protocol.h must stay C-compatible for the Arduino side. */
#include "assistive_tactile/vest_protocol.h"

int assistive_tactile_protocol_c_check(void);
int assistive_tactile_protocol_c_check(void)
{
  vest_packet_t p = { VEST_TYPE_COMMAND, 1, 0x5, { 10, 0, 30, 0 }, 200 };
  uint8_t buf[VEST_PACKET_SIZE];
  vest_packet_t q;
  vest_encode(&p, buf);
  return vest_decode(buf, &q);
}
