#!/usr/bin/env python3
"""A plain Python transcription of the listing (``legacy/luminaire.f``): the speed reference of
``benchmarks/bench_emulator_start.py``, not package code.

    python benchmarks/plain_listing.py DECK        # prints what the REAL*8 build prints

MAIN and SUBROUTINE ED in Python floats (binary64, as gfortran's ``-fdefault-real-8`` build of
the goldens), local variables, the arithmetic IFs as comparisons, ``X**2`` as ``X*X`` (as
gfortran expands it), the C library's sin and cos, and every WRITE formatted by Python's ``%``
operator (``%15.5f`` for ``F15.5``: the exact binary value rounded to nearest, as gfortran's F
editing).  It imports nothing but ``math`` and ``sys``: the smallest program that prints the
listing's output, against which the emulator's whole-process time is measured.

Left out, because a plain transcription has none of them: the emulator's guards (a post that
never lands, ED without a root, a NaN), the other arithmetics, the errata and options, the
deck's error messages and the 1967 blank rules (a field is ``float()`` of its ten columns, so
a deck must write its decimal points, as decks/*.dat do), and F-format overflow (``****``).
``tests/legacy/test_plain_listing.py`` checks that it prints, byte for byte, the golden printout of
gfortran's build (``golden/steel40.r8.txt``) and what ``deck-emulator run`` prints.
"""

import sys
from math import cos as COS, sin as SIN

ABS = abs


def read_cards(path):
    """The eight data cards' 64 F10.5 fields, as floats (``$`` cards skipped)."""
    with open(path) as f:
        cards = [line.rstrip("\r\n") for line in f if line.strip() and not line.startswith("$")]
    values = []
    for card in cards[:8]:
        card = card.ljust(80)
        values += [float(card[i:i + 10]) if card[i:i + 10].strip() else 0.0
                   for i in range(0, 80, 10)]
    return values


class _EDState:
    L = 0  # static in SUBROUTINE ED (zero at load, as -finit-local-zero)
    DH = 0.0  # static too: label 20 takes it when DF(D) is zero at entry


def ED(W1A, W2A, W3A, THDB, PHIDB, PSIDB, HI, PSIB, THB):
    """SUBROUTINE ED: returns D."""
    def DF(D):
        return D-((HI/2.)*(W3A+(COS((HI/2.)*(W2A*COS(D)+W1A*SIN(D)+THDB)+THB)/SIN((HI/2.)*(W2A*COS(D)+W1A*SIN(D)+THDB)+THB))*(W1A*COS(D)-W2A*SIN(D))+PSIDB)+PSIB)  # noqa: E501

    if _EDState.L - 25 <= 0:  # IF(L-25)21,21,22
        D = .15
    else:
        D = PSIB
    H = -0.01
    f = DF(D)
    lab = 1 if f < 0 else 20 if f == 0 else 10
    DH = _EDState.DH
    while True:
        if lab == 1:
            DH = D+H
            f = DF(DH)
            lab = 2 if f < 0 else 20 if f == 0 else 15
        elif lab == 2:
            D = DH
            lab = 1
        elif lab == 15:
            DH = D+H/2.
            lab = 20 if ABS(DF(DH))-.0001 <= 0 else 4
        elif lab == 4:
            f = DF(DH)
            lab = 5 if f < 0 else 20 if f == 0 else 3
        elif lab == 3:
            H = H/2.
            lab = 15
        elif lab == 5:
            D = DH
            H = H/2.
            lab = 15
        elif lab == 10:
            DH = D+H
            f = DF(DH)
            lab = 16 if f < 0 else 20 if f == 0 else 11
        elif lab == 11:
            D = DH
            lab = 10
        elif lab == 16:
            DH = D+H/2.
            lab = 20 if ABS(DF(DH))-.0001 <= 0 else 13
        elif lab == 13:
            f = DF(DH)
            lab = 12 if f < 0 else 20 if f == 0 else 14
        elif lab == 12:
            H = H/2.
            lab = 16
        elif lab == 14:
            D = DH
            H = H/2.
            lab = 16
        else:  # 20
            D = DH
            _EDState.L += 1
            _EDState.DH = DH
            return D


def _f(x, w):
    return "%*.5f" % (w, x)


def main(path, out):  # noqa: C901 - one program unit, as the listing's MAIN
    (V1B, V2B, V3B, VVB, F1B, F2B, F3B, PSIDB,
     THDB, PHIDB, W, WV, A, B, C, G,
     XCMB, YCMB, ZCMB, CK, W1B, W2B, W3B, HEIGHT,
     PSIB, THB, PHIB, SVB, XSO, YYSO, ZZSO, FNA,
     XPO, YYPO, ZZPO, XQO, YYQO, ZZQO, SVO, ALPHA,
     T1B, T2B, T3B, HLEN, TLEN, DELTA, YLFEN, YRFEN,
     TRLEN, HTRV, FSB, HTV, HHV, XRO, YYRO, ZZRO,
     XCO, YYCO, ZZCO, XTO, YYTO, ZZTO, CT, FCONST) = read_cards(path)
    w = out.append
    HI = 0.0004
    E = 0.0
    I = 0  # noqa: E741
    M = 0
    H = 0.0004
    Q = 0.0
    LL = 0
    N = 0
    DIFFB = 0.0
    T = 0.0
    YPO = YYPO*COS(DELTA)+ZZPO*SIN(DELTA)
    ZPO = -YYPO*SIN(DELTA)+ZZPO*COS(DELTA)
    YQO = YYQO*COS(DELTA)+ZZQO*SIN(DELTA)
    ZQO = -YYQO*SIN(DELTA)+ZZQO*COS(DELTA)
    YSO = YYSO*COS(DELTA)+ZZSO*SIN(DELTA)
    ZSO = -YYSO*SIN(DELTA)+ZZSO*COS(DELTA)
    YTO = YYTO*COS(DELTA)+ZZTO*SIN(DELTA)
    ZTO = -YYTO*SIN(DELTA)+ZZTO*COS(DELTA)
    YRO = YYRO*COS(DELTA)+ZZRO*SIN(DELTA)
    ZRO = -YYRO*SIN(DELTA)+ZZRO*COS(DELTA)
    YCO = YYCO*COS(DELTA)+ZZCO*SIN(DELTA)
    ZCO = -YYCO*SIN(DELTA)+ZZCO*COS(DELTA)
    XVSO = XSO*COS(ALPHA)-YYSO*SIN(ALPHA)
    XVTO = XTO*COS(ALPHA)-YYTO*SIN(ALPHA)
    lab = 125
    while True:
        if lab == 125:
            if Q-0.0004 < 0:  # 123
                W1A = 0.0
                W2A = 0.0545
                W3A = 0.0
                FSB = 10000.0
                F1B = -10000.0
                THDA = 0.0545
                PHIDA = 0.0
                PSIDA = 0.0
                THA = 0.000022
                PHIA = 0.0
                PSIA = 0.0
                lab = 124
            else:
                lab = 44
        elif lab == 44:
            W1A = ((H*T1B)/A)+H*(((B-C)/A)*W2B*W3B)+W1B
            W2A = (H/B)*T2B+H*(((C-A)/B)*W1B*W3B)+W2B
            W3A = (H/C)*T3B+H*(((A-B)/C)*W1B*W2B)+W3B
            D = ED(W1A, W2A, W3A, THDB, PHIDB, PSIDB, HI, PSIB, THB)
            PSIA = D
            PSIAD = PSIA*57.3
            PFORK = (W1A*COS(PSIA))-(W2A*SIN(PSIA))
            THA = (H/2.)*(W2A*COS(PSIA)+W1A*SIN(PSIA)+THDB)+THB
            THAD = THA*57.3
            PHIA = (H/2.)*((((SIN(THA))*PFORK)/((COS(THA))*COS(THA)-1.0))+PHIDB)+PHIB
            PHIAD = PHIA*57.3
            THDA = (W2A/COS(PSIA))+((SIN(PSIA))/COS(PSIA))*PFORK
            PHIDA = (-1.0/SIN(THA))*PFORK
            PSIDA = W3A-(COS(THA))*PHIDA
            lab = 124
        elif lab == 124:
            V1A = H*((F1B/W)+V2B*W3B-V3B*W2B)+V1B
            V2A = H*((F2B/W)+V3B*W1B-V1B*W3B)+V2B
            V3A = H*((F3B/W)+V1B*W2B-V2B*W1B)+V3B
            VVA = VVB+(H/WV)*FSB
            S1A = (H/2.)*(V1A+V1B)
            S2A = (H/2.)*(V2A+V2B)
            S3A = (H/2.)*(V3A+V3B)
            SVA = (H/2.)*(VVA+VVB)+SVB
            DIRC1X = (((-SIN(PHIA))*SIN(PSIA))+((COS(THA))*COS(PHIA))*COS(PSIA))
            DIRC1Y = (((COS(PHIA))*SIN(PSIA))+((COS(THA))*SIN(PHIA))*COS(PSIA))
            DIRC1Z = ((-SIN(THA))*COS(PSIA))
            DIRC2X = (((-SIN(PHIA))*COS(PSIA))-((COS(THA))*COS(PHIA))*SIN(PSIA))
            DIRC2Y = (((COS(PHIA))*COS(PSIA))-((COS(THA))*SIN(PHIA))*SIN(PSIA))
            DIRC2Z = ((SIN(THA))*SIN(PSIA))
            DIRC3X = ((SIN(THA))*COS(PHIA))
            DIRC3Y = ((SIN(THA))*SIN(PHIA))
            DIRC3Z = COS(THA)
            XCMA = S1A*DIRC1X+S2A*DIRC2X+S3A*DIRC3X+XCMB
            YCMA = S1A*DIRC1Y+S2A*DIRC2Y+S3A*DIRC3Y+YCMB
            ZCMA = S1A*DIRC1Z+S2A*DIRC2Z+S3A*DIRC3Z+ZCMB
            YYCMA = YCMA*COS(DELTA)-ZCMA*SIN(DELTA)
            ZZCMA = YCMA*SIN(DELTA)+ZCMA*COS(DELTA)
            SQUIGA = SIN(THA/2.)*SIN((PSIA-PHIA)/2.)
            ETAA = SIN(THA/2.)*COS((PSIA-PHIA)/2.)
            ZETAA = COS(THA/2.)*SIN((PSIA+PHIA)/2.)
            CHIA = COS(THA/2.)*COS((PSIA+PHIA)/2.)
            SQ, ET, ZE, CH = SQUIGA, ETAA, ZETAA, CHIA
            XPA = XCMA+(XPO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YPO)*((SQ*ET)-(ZE*CH))+(2.*ZPO)*((SQ*ZE)+(ET*CH))
            YPA = YCMA+(2.*XPO)*((SQ*ET)+(ZE*CH))+(YPO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZPO)*((ET*ZE)-(SQ*CH))
            ZPA = ZCMA+(2.*XPO)*((SQ*ZE)-(ET*CH))+(2.*YPO)*((ET*ZE)+(SQ*CH))+(ZPO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYPA = YPA*COS(DELTA)-ZPA*SIN(DELTA)
            ZZPA = YPA*SIN(DELTA)+ZPA*COS(DELTA)
            XQA = XCMA+(XQO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YQO)*((SQ*ET)-(ZE*CH))+(2.*ZQO)*((SQ*ZE)+(ET*CH))
            YQA = YCMA+(2.*XQO)*((SQ*ET)+(ZE*CH))+(YQO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZQO)*((ET*ZE)-(SQ*CH))
            ZQA = ZCMA+(2.*XQO)*((SQ*ZE)-(ET*CH))+(2.*YQO)*((ET*ZE)+(SQ*CH))+(ZQO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYQA = YQA*COS(DELTA)-ZQA*SIN(DELTA)
            ZZQA = YQA*SIN(DELTA)+ZQA*COS(DELTA)
            XSA = XCMA+(XSO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YSO)*((SQ*ET)-(ZE*CH))+(2.*ZSO)*((SQ*ZE)+(ET*CH))
            YSA = YCMA+(2.*XSO)*((SQ*ET)+(ZE*CH))+(YSO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZSO)*((ET*ZE)-(SQ*CH))
            ZSA = ZCMA+(2.*XSO)*((SQ*ZE)-(ET*CH))+(2.*YSO)*((ET*ZE)+(SQ*CH))+(ZSO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYSA = YSA*COS(DELTA)-ZSA*SIN(DELTA)
            ZZSA = YSA*SIN(DELTA)+ZSA*COS(DELTA)
            XVSA = XSA*COS(ALPHA)-YYSA*SIN(ALPHA)
            YVSA = XSA*SIN(ALPHA)+YYSA*COS(ALPHA)
            XRA = XCMA+(XRO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YRO)*((SQ*ET)-(ZE*CH))+(2.*ZRO)*((SQ*ZE)+(ET*CH))
            YRA = YCMA+(2.*XRO)*((SQ*ET)+(ZE*CH))+(YRO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZRO)*((ET*ZE)-(SQ*CH))
            ZRA = ZCMA+(2.*XRO)*((SQ*ZE)-(ET*CH))+(2.*YRO)*((ET*ZE)+(SQ*CH))+(ZRO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYRA = YRA*COS(DELTA)-ZRA*SIN(DELTA)
            ZZRA = YRA*SIN(DELTA)+ZRA*COS(DELTA)
            XVRA = XRA*COS(ALPHA)-YYRA*SIN(ALPHA)
            YVRA = XRA*SIN(ALPHA)+YYRA*COS(ALPHA)
            XTA = XCMA+(XTO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YTO)*((SQ*ET)-(ZE*CH))+(2.*ZTO)*((SQ*ZE)+(ET*CH))
            YTA = YCMA+(2.*XTO)*((SQ*ET)+(ZE*CH))+(YTO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZTO)*((ET*ZE)-(SQ*CH))
            ZTA = ZCMA+(2.*XTO)*((SQ*ZE)-(ET*CH))+(2.*YTO)*((ET*ZE)+(SQ*CH))+(ZTO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYTA = YTA*COS(DELTA)-ZTA*SIN(DELTA)
            ZZTA = YTA*SIN(DELTA)+ZTA*COS(DELTA)
            XVTA = XTA*COS(ALPHA)-YYTA*SIN(ALPHA)
            YVTA = XTA*SIN(ALPHA)+YYTA*COS(ALPHA)
            POSLEN = ABS(XVSA-XVSO)
            TDISP = ABS(XVTA-XVTO)
            CARLEN = ABS(SVA-SVO)
            DIFF = POSLEN-CARLEN
            DIFFT = TDISP-CARLEN
            # CALCULATION OF FORCES
            if Q-.0004 < 0:  # 83
                FSA = 1320.0
                to85 = True
            else:  # 84
                if DIFF-0.01 <= 0:  # 356
                    FSA = ABS(CK*((SVO-SVA)-(XVSO-XVSA)))
                    FSA = 0.8*FSA
                else:  # 357
                    FSA = ABS(CT*((SVO-SVA)-(XVTO-XVTA)))
                    FSA = 0.8*FSA
                    ZSA = ZTA
                    XSA = XTA
                    YSA = YTA
                # 358, 501, 502, 504
                if LL-20 >= 0 and DIFF-DIFFB >= 0 and FSA-FCONST >= 0:
                    FSA = FCONST
                # 600, 102: 101 or 104
                to85 = not (XQA+0.083333 <= 0 or XQA+0.083333-0.004 <= 0)
                if not to85:
                    FFXA = 0.0
            if to85:  # 85
                CFA = 0.25
                FNAC = 635.0
                T = 300.0
                FFXA = 3.1*T
            if XQA+0.4166 <= 0:  # 105, 107
                FNA = 0.0
            # 106
            FFYA = 0.0
            FSXA = FSA*COS(ALPHA)
            FSYA = FSA*SIN(ALPHA)
            F1A = (FFXA-FSXA)*(DIRC1X)+(FSYA*COS(DELTA)+FNA*SIN(DELTA)-W*G*SIN(DELTA)-FFYA*COS(DELTA))*(DIRC1Y)+(FFYA*SIN(DELTA)+FNA*COS(DELTA)-W*G*COS(DELTA)-FSYA*SIN(DELTA))*(DIRC1Z)  # noqa: E501
            F2A = (FFXA-FSXA)*(DIRC2X)+(FSYA*COS(DELTA)+FNA*SIN(DELTA)-W*G*SIN(DELTA)-FFYA*COS(DELTA))*(DIRC2Y)+(FFYA*SIN(DELTA)+FNA*COS(DELTA)-W*G*COS(DELTA)-FSYA*SIN(DELTA))*(DIRC2Z)  # noqa: E501
            F3A = (FFXA-FSXA)*(DIRC3X)+(FSYA*COS(DELTA)+FNA*SIN(DELTA)-W*G*SIN(DELTA)-FFYA*COS(DELTA))*(DIRC3Y)+(FFYA*SIN(DELTA)+FNA*COS(DELTA)-W*G*COS(DELTA)-FSYA*SIN(DELTA))*(DIRC3Z)  # noqa: E501
            TXA = (FFYA*COS(DELTA))*(ZQA-ZCMA)+(FNA*COS(DELTA))*(YQA-YCMA)-(FNA*SIN(DELTA))*(ZQA-ZCMA)+(FFYA*SIN(DELTA))*(YQA-YCMA)-(FSYA*COS(DELTA))*(ZSA-ZCMA)-(FSYA*SIN(DELTA))*(YSA-YCMA)  # noqa: E501
            TYA = FFXA*(ZQA-ZCMA)-(FNA*COS(DELTA))*(XQA-XCMA)-FSXA*(ZSA-ZCMA)-(FFYA*SIN(DELTA))*(XQA-XCMA)+(FSYA*SIN(DELTA))*(XSA-XCMA)  # noqa: E501
            TZA = -FFXA*(YQA-YCMA)-(FFYA*COS(DELTA))*(XQA-XCMA)+FSXA*(YSA-YCMA)+(FSYA*COS(DELTA))*(XSA-XCMA)+(FNA*SIN(DELTA))*(XQA-XCMA)  # noqa: E501
            T1A = (TXA*DIRC1X)+(TYA*DIRC1Y)+(TZA*DIRC1Z)
            T2A = (TXA*DIRC2X)+(TYA*DIRC2Y)+(TZA*DIRC2Z)
            T3A = (TXA*DIRC3X)+(TYA*DIRC3Y)+(TZA*DIRC3Z)
            # TIME CALCULATION
            LL = LL+1
            Q = Q+H
            E = E+.0004
            if E-0.0016 < 0:
                lab = 54
            else:
                E = 0.0
                lab = 88
        elif lab == 88:
            w("1")
            w("     THE VALUE OF VVA IS " + _f(VVA, 15))
            w("")
            w("     THE VALUE OF SVA IS " + _f(SVA, 15))
            w("")
            w("     THE VALUE OF THA IS " + _f(THAD, 15))
            w("")
            w("     THE VALUE OF PHIA IS " + _f(PHIAD, 15))
            w("")
            w("     THE VALUE OF PSIA IS " + _f(PSIAD, 15))
            w("")
            w("     THE VALUE OF XCMA IS " + _f(XCMA, 15))
            w("")
            w("     THE VALUE OF XPA IS " + _f(XPA, 15))
            w("")
            w("     THE VALUE OF XSA IS " + _f(XSA, 15))
            w("")
            w("     THE VALUE OF XQA IS " + _f(XQA, 15))
            w("")
            w("     THE VALUE OF YYCMA IS " + _f(YYCMA, 15))
            w("")
            w("     THE VALUE OF YYPA IS " + _f(YYPA, 15) + " " * 30 + "THE VALUE OF XRA IS " + _f(XRA, 15))
            w("")
            w("     THE VALUE OF YYSA IS " + _f(YYSA, 15) + " " * 30 + "THE VALUE OF YYRA IS " + _f(YYRA, 15))
            w("")
            w("     THE VALUE OF YYQA IS " + _f(YYQA, 15) + " " * 30 + "THE VALUE OF ZZRA IS " + _f(ZZRA, 15))
            w("")
            w("     THE VALUE OF ZXCMA IS " + _f(ZZCMA, 15))
            w("")
            w("     THE VALUE OF ZZPA IS " + _f(ZZPA, 15))
            w("")
            w("     THE VALUE OF ZZSA IS " + _f(ZZSA, 15))
            w("")
            w("     THE VALUE OF ZZQA IS " + _f(ZZQA, 15))
            w("")
            w("     THE VALUE OF FSA IS " + _f(FSA, 15))
            w("")
            w("     THE VALUE OF DIFF IS " + _f(DIFF, 15))
            w("")
            w("     THE VALUE OF TIME IS %10.6f" % Q)
            lab = 54
        elif lab == 54:
            if M-1 < 0:  # 55
                if DIFF < 0:
                    lab = 41
                elif DIFF == 0:
                    lab = 354
                elif DIFF-0.01 <= 0:  # 43 -> 56
                    M = 1
                    lab = 88
                else:
                    lab = 108
            elif M-1 == 0:
                lab = 354
            elif N-1 == 0:  # 350
                lab = 42
            elif DIFFT < 0:  # 351
                lab = 41
            elif DIFFT == 0:
                lab = 42
            elif DIFFT-0.01 <= 0:  # 352 -> 353
                N = 1
                lab = 88
            else:
                lab = 108
        elif lab == 108:
            Q = Q-H
            H = H/2.
            HI = HI/2.
            lab = 44
        elif lab == 354:
            M = 2
            H = 0.0004
            HI = 0.0004
            w("")
            w("")
            w("     THE POST HAS LOST CONTACT WITH FIRST SPRING")
            lab = 41
        elif lab == 41:
            V1B = V1A
            V2B = V2A
            V3B = V3A
            W1B = W1A
            W2B = W2A
            W3B = W3A
            T1B = T1A
            T2B = T2A
            T3B = T3A
            F1B = F1A
            F2B = F2A
            F3B = F3A
            DIFFB = DIFF
            VVB = VVA
            THB = THA
            PHIB = PHIA
            PSIB = PSIA
            THDB = THDA
            PHIDB = PHIDA
            PSIDB = PSIDA
            FSB = FSA
            SVB = SVA
            XCMB = XCMA
            YCMB = YCMA
            ZCMB = ZCMA
            lab = 125
        elif lab == 42:
            w("")
            w("")
            w("     THE POST HAS LOST CONTACT WITH THE VEHICLE")
            H = 0.0004
            HI = 0.0004
            E = 0.0
            XCMFB = XCMA
            YCMFB = YCMA
            ZCMFB = ZCMA
            THDFB = THDA
            PHIDFB = PHIDA
            PSIDFB = PSIDA
            THFB = THA
            PHIFB = PHIA
            PSIFB = PSIA
            W1FB = W1A
            W2FB = W2A
            W3FB = W3A
            V1FB = V1A
            V2FB = V2A
            V3FB = V3A
            VVFB = VVA
            TF = Q
            SVFB = SVA
            lab = 57
        elif lab == 57:
            T = TF+H
            W1FA = H*((B-C)/A)*W2FB*W3FB+W1FB
            W2FA = H*((C-A)/B)*W1FB*W3FB+W2FB
            W3FA = H*((A-B)/C)*W1FB*W2FB+W3FB
            D = ED(W1FA, W2FA, W3FA, THDFB, PHIDFB, PSIDFB, HI, PSIFB, THFB)
            PSIFA = D
            PSIFAD = PSIFA*57.3
            PFORKF = (W1FA*COS(PSIFA))-(W2FA*SIN(PSIFA))
            THFA = (H/2.)*(W2FA*COS(PSIFA)+W1FA*SIN(PSIFA)+THDFB)+THFB
            THFAD = THFA*57.3
            PHIFA = (H/2.)*((((SIN(THFA))*PFORKF)/((COS(THFA))*COS(THFA)-1.0))+PHIDFB)+PHIFB
            PHIFAD = PHIFA*57.3
            THDFA = (W2FA/COS(PSIFA))+((SIN(PSIFA))/COS(PSIFA))*PFORKF
            PHIDFA = (-1.0/SIN(THFA))*PFORKF
            PSIDFA = W3FA-(COS(THFA))*PHIDFA
            F1FB = W*G*COS(DELTA)*SIN(THFB)*COS(PSIFB)-W*G*SIN(DELTA)*(COS(PHIFB)*SIN(PSIFB)+COS(THFB)*SIN(PHIFB)*COS(PSIFB))  # noqa: E501
            F2FB = -W*G*COS(DELTA)*SIN(THFB)*SIN(PSIFB)-W*G*SIN(DELTA)*(COS(PHIFB)*COS(PSIFB)-COS(THFB)*SIN(PHIFB)*SIN(PSIFB))  # noqa: E501
            F3FB = -W*G*COS(DELTA)*COS(THFB)-W*G*SIN(DELTA)*SIN(THFB)*SIN(PHIFB)
            V1FA = H*((F1FB/W)+V2FB*W3FB-V3FB*W2FB)+V1FB
            V2FA = H*((F2FB/W)+V3FB*W1FB-V1FB*W3FB)+V2FB
            V3FA = H*((F3FB/W)+V1FB*W2FB-V2FB*W1FB)+V3FB
            VVFA = VVFB
            S1FA = (H/2.)*(V1FA+V1FB)
            S2FA = (H/2.)*(V2FA+V2FB)
            S3FA = (H/2.)*(V3FA+V3FB)
            SVFA = (H/2.)*(VVFA+VVFB)+SVFB
            XBUMP = SVFA-HLEN
            XENTOP = SVFA+TLEN
            XTAIL = XENTOP+TRLEN
            XCMFA = (S1FA)*((-SIN(PHIFA))*(SIN(PSIFA))+((COS(THFA))*(COS(PHIFA))*(COS(PSIFA))))+(S2FA)*((-SIN(PHIFA))*(COS(PSIFA))-((COS(THFA))*(COS(PHIFA))*SIN(PSIFA)))+(S3FA)*((SIN(THFA))*COS(PHIFA))+XCMFB  # noqa: E501
            YCMFA = (S1FA)*((COS(PHIFA))*(SIN(PSIFA))+((COS(THFA))*(SIN(PHIFA))*COS(PSIFA)))+(S2FA)*((COS(PHIFA))*(COS(PSIFA))-((COS(THFA))*(SIN(PHIFA))*SIN(PSIFA)))+(S3FA)*((SIN(THFA))*SIN(PHIFA))+YCMFB  # noqa: E501
            ZCMFA = (S1FA)*(-SIN(THFA))*(COS(PSIFA))+((S2FA)*(SIN(THFA))*(SIN(PSIFA)))+(S3FA)*(COS(THFA))+ZCMFB  # noqa: E501
            YYCMFA = YCMFA*COS(DELTA)-ZCMFA*SIN(DELTA)
            ZZCMFA = YCMFA*SIN(DELTA)+ZCMFA*COS(DELTA)
            SQ = SIN(THFA/2.)*SIN((PSIFA-PHIFA)/2.)
            ET = SIN(THFA/2.)*COS((PSIFA-PHIFA)/2.)
            ZE = COS(THFA/2.)*SIN((PSIFA+PHIFA)/2.)
            CH = COS(THFA/2.)*COS((PSIFA+PHIFA)/2.)
            XPFA = XCMFA+(XPO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YPO)*((SQ*ET)-(ZE*CH))+(2.*ZPO)*((SQ*ZE)+(ET*CH))
            YPFA = YCMFA+(2.*XPO)*((SQ*ET)+(ZE*CH))+(YPO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZPO)*((ET*ZE)-(SQ*CH))
            ZPFA = ZCMFA+(2.*XPO)*((SQ*ZE)-(ET*CH))+(2.*YPO)*((ET*ZE)+(SQ*CH))+(ZPO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYPFA = YPFA*COS(DELTA)-ZPFA*SIN(DELTA)
            ZZPFA = YPFA*SIN(DELTA)+ZPFA*COS(DELTA)
            XVPFA = XPFA*COS(ALPHA)-YYPFA*SIN(ALPHA)
            YVPFA = XPFA*SIN(ALPHA)+YYPFA*COS(ALPHA)
            XQFA = XCMFA+(XQO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YQO)*((SQ*ET)-(ZE*CH))+(2.*ZQO)*((SQ*ZE)+(ET*CH))
            YQFA = YCMFA+(2.*XQO)*((SQ*ET)+(ZE*CH))+(YQO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZQO)*((ET*ZE)-(SQ*CH))
            ZQFA = ZCMFA+(2.*XQO)*((SQ*ZE)-(ET*CH))+(2.*YQO)*((ET*ZE)+(SQ*CH))+(ZQO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYQFA = YQFA*COS(DELTA)-ZQFA*SIN(DELTA)
            ZZQFA = YQFA*SIN(DELTA)+ZQFA*COS(DELTA)
            XRFA = XCMFA+(XRO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YRO)*((SQ*ET)-(ZE*CH))+(2.*ZRO)*((SQ*ZE)+(ET*CH))
            YRFA = YCMFA+(2.*XRO)*((SQ*ET)+(ZE*CH))+(YRO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZRO)*((ET*ZE)-(SQ*CH))
            ZRFA = ZCMFA+(2.*XRO)*((SQ*ZE)-(ET*CH))+(2.*YRO)*((ET*ZE)+(SQ*CH))+(ZRO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYRFA = YRFA*COS(DELTA)-ZRFA*SIN(DELTA)
            ZZRFA = YRFA*SIN(DELTA)+ZRFA*COS(DELTA)
            XVRFA = XRFA*COS(ALPHA)-YYRFA*SIN(ALPHA)
            YVRFA = XRFA*SIN(ALPHA)+YYRFA*COS(ALPHA)
            XCFA = XCMFA+(XCO)*(SQ*SQ-ET*ET-ZE*ZE+CH*CH)+(2.*YCO)*((SQ*ET)-(ZE*CH))+(2.*ZCO)*((SQ*ZE)+(ET*CH))
            YCFA = YCMFA+(2.*XCO)*((SQ*ET)+(ZE*CH))+(YCO)*(-SQ*SQ+ET*ET-ZE*ZE+CH*CH)+(2.*ZCO)*((ET*ZE)-(SQ*CH))
            ZCFA = ZCMFA+(2.*XCO)*((SQ*ZE)-(ET*CH))+(2.*YCO)*((ET*ZE)+(SQ*CH))+(ZCO)*(-SQ*SQ-ET*ET+ZE*ZE+CH*CH)
            YYCFA = YCFA*COS(DELTA)-ZCFA*SIN(DELTA)
            ZZCFA = YCFA*SIN(DELTA)+ZCFA*COS(DELTA)
            XVCFA = XCFA*COS(ALPHA)-YYCFA*SIN(ALPHA)
            YVCFA = XCFA*SIN(ALPHA)+YYCFA*COS(ALPHA)
            E = E+0.0002
            if E-0.008 < 0:
                lab = 77
            else:  # 80
                E = 0.0
                lab = 98
        elif lab == 98:
            w("1")
            w("     THE VALUE OF THFA IS " + _f(THFAD, 10))
            w("")
            w("     THE VALUE OF PHIFA IS " + _f(PHIFAD, 10))
            w("")
            w("     THE VALUE OF PSIFA IS " + _f(PSIFAD, 10))
            w("")
            w("     THE VALUE OF XCMFA IS " + _f(XCMFA, 10))
            w("")
            w("     THE VALUE OF XPFA IS " + _f(XPFA, 10))
            w("")
            w("     THE VALUE OF XQFA IS " + _f(XQFA, 10))
            w("")
            w("     THE VALUE OF XRFA IS " + _f(XRFA, 10))
            w("")
            w("     THE VALUE OF XCFA IS " + _f(XCFA, 15))
            w("")
            w("     THE VALUE OF YYCMFA IS " + _f(YYCMFA, 15))
            w("")
            w("     THE VALUE OF YYPFA IS " + _f(YYPFA, 15))
            w("")
            w("     THE VALUE OF YYQFA IS " + _f(YYQFA, 15))
            w("")
            w("     THE VALUE OF YYRFA IS " + _f(YYRFA, 15))
            w("")
            w("     THE VALUE OF YYCFA IS " + _f(YYCFA, 15))
            w("")
            w("     THE VALUE OF ZZCMFA IS " + _f(ZZCMFA, 15))
            w("")
            w("     THE VALUE OF ZZPFA IS " + _f(ZZPFA, 15))
            w("")
            w("     THE VALUE OF ZZQFA IS " + _f(ZZQFA, 15))
            w("")
            w("     THE VALUE OF ZZRFA IS " + _f(ZZRFA, 15))
            w("")
            w("     THE VALUE OF ZYCFA IS " + _f(ZZCFA, 15))
            w("")
            w("     THE VALUE OF SVFA IS " + _f(SVFA, 10))
            w("")
            w("     THE VALUE OF TIME IS " + _f(T, 10))
            lab = 77
        elif lab == 77:
            if I-1 == 0:
                return  # 82 STOP
            lab = _checks(ZZPFA, ZZQFA, ZZRFA, ZZCFA, HEIGHT, YVPFA, XVPFA, YVRFA, XVRFA,
                          YVCFA, XVCFA, YLFEN, YRFEN, XBUMP, SVFA, XENTOP, XTAIL, HHV, HTV, HTRV)
            if lab == 400:
                TF = T
                THFB = THFA
                PHIFB = PHIFA
                PSIFB = PSIFA
                VVFB = VVFA
                V1FB = V1FA
                V2FB = V2FA
                V3FB = V3FA
                W1FB = W1FA
                W2FB = W2FA
                W3FB = W3FA
                THDFB = THDFA
                PHIDFB = PHIDFA
                PSIDFB = PSIDFA
                XCMFB = XCMFA
                YCMFB = YCMFA
                ZCMFB = ZCMFA
                SVFB = SVFA
                lab = 57
            else:  # a hit: its message, I=1, GO TO 98
                I = 1  # noqa: E741
                w("")
                if lab != 140:
                    w("")
                w("     THE POST HAS HIT " + _HITS[lab])
                lab = 98


_HITS = {140: "THE GROUND WITH POINT C", 96: "THE GROUND WITH POINT Q",
         93: "THE GROUND WITH POINT P", 109: "THE GROUND WITH POINT R",
         236: "THE HOOD OF THE VEHICLE", 238: "THE WINDSHIELD OF THE VEHICLE",
         240: "THE TOP OF THE VEHICLE", 247: "THE TRUNK OF THE VEHICLE"}


def _point(Z, YV, XV, YLFEN, YRFEN, XBUMP, SVFA, XENTOP, XTAIL, HHV, HTV, HTRV):
    """Labels 500-246 (P), 112-262 (R), 300-462 (C): the vehicle check of one point; None
    when the point is clear of the car (the next check)."""
    if YV-YLFEN < 0 or (YV-YLFEN > 0 and YV-YRFEN > 0):
        return None
    if XV-XBUMP < 0:
        return None
    if XV-XBUMP == 0 or XV-SVFA < 0:  # the hood
        return 236 if Z-HHV == 0 or ABS(Z-HHV)-0.1 <= 0 else None
    if XV-SVFA == 0 or XV-SVFA-0.1 <= 0:  # the windshield
        lab = 233
    elif XV-XENTOP < 0:
        lab = 233
    elif XV-XENTOP == 0:
        return 240
    elif XV-XTAIL <= 0:  # the trunk
        return 247 if Z-HTRV == 0 or ABS(Z-HTRV)-0.1 <= 0 else None
    else:
        return None
    if Z-HTV < 0:
        return 238
    if Z-HTV == 0 or ABS(Z-HTV)-0.1 <= 0:
        return 240
    return None


def _checks(ZZPFA, ZZQFA, ZZRFA, ZZCFA, HEIGHT, YVPFA, XVPFA, YVRFA, XVRFA, YVCFA, XVCFA,
            YLFEN, YRFEN, XBUMP, SVFA, XENTOP, XTAIL, HHV, HTV, HTRV):
    """Labels 81-462: the ground, then the car, for P, Q, R, C; the label it goes to."""
    if ZZPFA+HEIGHT == 0 or ABS(ZZPFA+HEIGHT)-0.1 <= 0:
        return 93
    if ZZQFA+HEIGHT == 0 or ABS(ZZQFA+HEIGHT)-0.01 <= 0:
        return 96
    if ZZRFA+HEIGHT == 0 or ABS(ZZRFA+HEIGHT)-0.1 <= 0:
        return 109
    if ZZCFA+HEIGHT == 0 or ABS(ZZCFA+HEIGHT)-0.1 <= 0:
        return 140
    car = (YLFEN, YRFEN, XBUMP, SVFA, XENTOP, XTAIL, HHV, HTV, HTRV)
    for Z, YV, XV in ((ZZPFA, YVPFA, XVPFA), (ZZRFA, YVRFA, XVRFA), (ZZCFA, YVCFA, XVCFA)):
        hit = _point(Z, YV, XV, *car)
        if hit is not None:
            return hit
    return 400


if __name__ == "__main__":
    records = []
    main(sys.argv[1], records)
    sys.stdout.write("".join(r + "\n" for r in records))
