// Log lines from the UART TX pin (tools/pic-module/uart_lines.h).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "pic-module/uart_lines.h"

using chainsim::pic::UartLines;

namespace {

// the edges a UART sending `text` at `bit` cycles per bit makes, from `at`
struct Wire {
  UartLines* rx;
  double bit;
  uint64_t at;
  bool level = true;
  void set(double t, bool l) {
    if (l != level) rx->edge(static_cast<uint64_t>(t), l);
    level = l;
  }
  void send(const std::string& text, double gap_bits = 0) {
    double t = static_cast<double>(at);
    for (unsigned char c : text) {
      set(t, false);  // start bit
      for (int b = 0; b < 8; ++b) set(t + (1 + b) * bit, (c >> b) & 1u);
      set(t + 9 * bit, true);  // stop bit
      t += (10 + gap_bits) * bit;
    }
    at = static_cast<uint64_t>(t);
  }
};

}  // namespace

TEST(UartLines, DecodesTheBoardsBaudRateAtTheNominalOne) {
  // hal-pic's 116279 baud (SPBRG 42) read by a 115200-baud receiver: 43.0
  // cycles per bit against 43.4
  UartLines rx(5e6 / 115200.0, 95);
  Wire w{&rx, 5e6 / 116279.0, 1000};
  w.send("start at ms 19\r\n");
  w.send("chain: RRRR (4 modules)\r\n", 3.5);
  rx.advance(w.at + 1000);
  ASSERT_EQ(rx.lines_waiting(), 2u);
  EXPECT_EQ(rx.pop_line(), "start at ms 19");
  EXPECT_EQ(rx.pop_line(), "chain: RRRR (4 modules)");
  EXPECT_EQ(rx.framing_errors(), 0u);
}

TEST(UartLines, TheLastByteIsDecodedOnceItsStopBitHasPassed) {
  UartLines rx(43.4, 95);
  Wire w{&rx, 43.4, 0};
  w.send("x\n");
  // the frame of '\n' (0x0A) ends with a high stop bit: no edge after it
  EXPECT_FALSE(rx.has_line());
  rx.advance(w.at);
  ASSERT_TRUE(rx.has_line());
  EXPECT_EQ(rx.pop_line(), "x");
}

TEST(UartLines, ALongLineIsCutAndABreakIsAFramingError) {
  UartLines rx(43.4, 5);
  Wire w{&rx, 43.4, 0};
  w.send("abcdefgh\n");
  rx.advance(w.at + 100);
  EXPECT_EQ(rx.pop_line(), "abcde");
  // a break: the line low for longer than a frame
  rx.edge(w.at + 200, false);
  rx.edge(w.at + 200 + 43 * 20, true);
  rx.advance(w.at + 5000);
  EXPECT_EQ(rx.framing_errors(), 1u);
}
