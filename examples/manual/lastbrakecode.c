/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4LastBrakeCode, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include <stdio.h>
#include "x4step.h"

char codes[2];

int main(void)
{
    X4Init(1);           // X4Step starten und
    codes[0] = 28;      // LPT2 verwenden
    codes[1] = 0;       // ENTER-Taste soll abbrechen
    X4BrakeCodes(codes); // Feld mit \0 abschließen
                       // Abbruchtasten definieren
    X4MovePos(1,1000,50); // Achse 1 endlos fahren mit
                       // 1000 Hz und 50 ms Rampe
    while (X4GetState()) // warten, bis mit ESC oder
    ;                       // ENTER abgebrochen wird
    switch (X4LastBrakeCode()) // Tastencode auswerten
    {
        case 1 :
            printf("ESC hat abgebrochen\n");
            break;
        case 28 :
            printf("ENTER hat abgebrochen\n");
            break;
        default :
            break;
    }
    X4ReInit();         // X4Step beenden
    return 0;
}
