// Timer2 held by tone(): its set-up (TCCR2A = 0) disconnects OC2A and OC2B, so PWM on pins 10 and
// 9 stops while a tone plays, as on the Mega.
#pragma once

bool sear_tone_timer2_taken();
// Called when tone() takes Timer2: stops the PWM analogWrite() started on 9 and 10 (wiring.cpp).
void sear_tone_take_timer2();
