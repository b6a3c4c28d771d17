// An MPU-6050 read over Wire the way most sketches do: wake it (PWR_MGMT_1 = 0), then every 100 ms
// point at ACCEL_XOUT_H with endTransmission(false) and read the 14 bytes of accelerometer,
// temperature and gyro with a repeated start. Prints the accelerations in g (+-2 g, 16384 LSB/g)
// and the rates in deg/s (+-250 deg/s, 131 LSB/(deg/s)).
#include <Wire.h>

const uint8_t MPU = 0x68;

int16_t word16() {
  const int hi = Wire.read();
  return (int16_t)(hi << 8 | Wire.read());
}

void setup() {
  Serial.begin(115200);
  Wire.begin();
  Wire.setClock(400000);
  Wire.beginTransmission(MPU);
  Wire.write(0x6B);  // PWR_MGMT_1
  Wire.write(0);     // wake up
  const uint8_t status = Wire.endTransmission();
  Serial.print(F("MPU-6050 wake: "));
  Serial.println(status == 0 ? F("ok") : F("no answer"));
}

void loop() {
  Wire.beginTransmission(MPU);
  Wire.write(0x3B);  // ACCEL_XOUT_H
  Wire.endTransmission(false);
  if (Wire.requestFrom(MPU, (uint8_t)14) == 14) {
    const float ax = word16() / 16384.0, ay = word16() / 16384.0, az = word16() / 16384.0;
    word16();  // temperature
    const float gx = word16() / 131.0, gy = word16() / 131.0, gz = word16() / 131.0;
    Serial.print(F("a "));
    Serial.print(ax, 2);
    Serial.print(' ');
    Serial.print(ay, 2);
    Serial.print(' ');
    Serial.print(az, 2);
    Serial.print(F(" g, w "));
    Serial.print(gx, 1);
    Serial.print(' ');
    Serial.print(gy, 1);
    Serial.print(' ');
    Serial.print(gz, 1);
    Serial.println(F(" deg/s"));
  }
  delay(100);
}
