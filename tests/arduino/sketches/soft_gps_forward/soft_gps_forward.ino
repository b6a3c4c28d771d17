// Forwards what a GPS on a soft UART (RX 10, TX 11, 9600 baud) sends to the console at 115200
// baud, fast enough never to fall behind. Built for both engines: on the AVR engine with the
// genuine SoftwareSerial, which receives from pin-change interrupts on pin 10.
#include <SoftwareSerial.h>

SoftwareSerial gps(10, 11);

void setup() {
  Serial.begin(115200);
  gps.begin(9600);
}

void loop() {
  while (gps.available()) Serial.write(gps.read());
}
