#pragma once
// The seed's card deck (BRL-CR-670 Appendix A, cards 0-15) as data, and its reader. Its pieces:
// input/deck_options.hpp (the `$ key = value` extensions), input/deck_cards.hpp (the cards as data) and
// input/deck_reader.hpp (read_deck); input/deck_scene.hpp builds the mesh and checks what refers to it.
//
// Readings of what the seed leaves open (also in docs/decks.md):
//  * Deck formats: `saac` (default; SAAC/SAAC2: a yield card, card 11, follows each material's
//    property cards; an all-blank yield card keeps that material elastic), `saac3` (SAAC3/SAAC3X: as
//    saac with the rate card, card 0, first) and `elastic` (SAAS/SAGA decks: no yield cards). In the
//    saac formats material number 2 marks gap elements (seed Data 6 note); in elastic decks it is an
//    ordinary material.
//  * NUMTC >= 1: that many (r, z, T) cards; -2: one constant-temperature card; 0: none (T = TREF).
//  * Cards 7 and 8 appear only when IPLLOT = 1. Card 15 (transverse shear) count is NUMST.
//  * Per load step: the inertia card (when INERT != 0, and only in the first block when INCI = 0),
//    then NUMPC pressure, NUMSC shear and NUMST transverse-shear cards (only in the first block when
//    INCF = 0). The values are the increments of that step; a block given once repeats every step.
//  * BETA and ALPHA (card 6) are in degrees.
//
// Extensions (options the seed's input lacks) are lines `$ key = value` before the first card; a
// line that is only `$` or `$ text` without `=` is a comment. The same keys can be set from the
// command line (gapfe --set key=value), so legacy decks stay untouched. See ModelOptions.
#include "gapfe/input/deck_cards.hpp"
#include "gapfe/input/deck_options.hpp"
#include "gapfe/input/deck_reader.hpp"
