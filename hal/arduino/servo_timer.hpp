// Which 16-bit timers Servo objects have taken: on the Mega the library takes Timer5 for the first
// 12 servos, then Timer1, Timer3 and Timer4, and a taken timer's PWM pins stop (44-46 for Timer5).
#pragma once

bool sear_servo_timer5_taken();
// Called by the first Servo::attach(): stops the PWM analogWrite() started on 44..46 (wiring.cpp).
void sear_servo_take_timer5();
