#!/usr/bin/env bash
# Paper Figs. 10 and 11 -- the limit friction coefficient mu_limit(w) of the Dahl and LuGre
# laws (Fig. 10: full stick, i.e. pre-sliding, iff mu >= mu_limit), and its maximum over
# the frequency as the contact stiffness ratio wb grows, for several contact damping
# ratios xi (Fig. 11).
#
# The paper: mu_limit grows with the frequency and is maximal at the resonances; LuGre's is
# below Dahl's (Fig. 10). It tends to the Coulomb limit coefficient as wb grows, and more
# internal damping lowers it (Fig. 11).
#
# This script: `hbf analytic --law dahl|lugre|coulomb` (column mu_limit; the closed forms
# re-derived in include/hbf/analytic.hpp: paper eqs. 25 and 27 lack the factor fe, so the
# paper's curves are ours at fe = 1, used here). Fig. 10 (fig10_limit_friction.png):
# mu_limit(w) for r = 0.1, wa = 1, wb = 0.4, xi = 0.01, with Coulomb's, and the ratio
# LuGre/Dahl. Fig. 11 (fig11_max_limit_friction.png): max over w in [0.5, 1.6] of
# mu_limit for wb = 0.1 ... 100 and xi = 0.01, 0.05, 0.1, 0.2 (`hbf analytic --sweep wb`:
# converged to 1e-13 in w even where the LuGre peaks are far narrower than any grid), and mu_limit(w) for xi = 0.1 and growing wb against Coulomb's.
#
# Differences from the paper, and why:
# - Fig. 10: "LuGre below Dahl" holds only near the two stuck resonances (w = 0.878, 1.225),
#   where Dahl's coefficient is infinite (undamped) and LuGre's finite. Elsewhere LuGre's is
#   slightly ABOVE Dahl's (0.03% at w = 0.5 to 0.3% at w = 1.6): its contact force
#   r (wb^2 + 2 i xi wb w) D has a larger modulus for the same relative motion, and the
#   relative motion hardly changes (exact closed forms; lower panel).
# - Fig. 11: the maximum over w does not tend to a finite Coulomb value. Coulomb's
#   mu_limit = fe r w^2 / |1 - (1+r) w^2| is infinite at the stuck resonance
#   w = 1/sqrt(1+r) = 0.953, and Dahl's (xi = 0) at both resonances: their maxima are
#   infinite (any finite value, e.g. the paper's, is a property of the frequency grid). For
#   LuGre (xi > 0) the maximum is finite, lower for larger xi (as the paper says), but it
#   GROWS without bound with wb: the stiffer contact moves less, so its damper dissipates
#   less and the stuck resonance becomes undamped (the max grows roughly like wb^3 for large
#   wb). The convergence to Coulomb holds pointwise in w (right panel of Fig. 11), not for
#   the maximum. We cannot tell which quantity the paper's Fig. 11 plots.
source "$(dirname "$0")/common.sh"

# Fig. 10
hbf analytic --law coulomb --fe 1 --points 11001 --out "$OUT/fig10_coulomb.csv"
hbf analytic --law dahl --fe 1 --wb 0.4 --points 11001 --out "$OUT/fig10_dahl.csv"
hbf analytic --law lugre --fe 1 --wb 0.4 --xi 0.01 --points 11001 --out "$OUT/fig10_lugre.csv"
# LuGre / Dahl ratio (same frequency grid, column 6 = mu_limit)
paste -d, "$OUT/fig10_dahl.csv" "$OUT/fig10_lugre.csv" |
  awk -F, 'NR == 1 { print "w,mu_limit_dahl,mu_limit_lugre,ratio"; next }
           { r = ($6 != "" && $13 != "" && $6 > 0) ? $13 / $6 : ""; print $1 "," $6 "," $13 "," r }' \
  >"$OUT/fig10_ratio.csv"

# Fig. 11: maximum of LuGre's mu_limit over w in [0.5, 1.6], `hbf analytic --sweep wb` (as
# mu_limit_max of --summary: a 2001-point grid plus the stuck resonances, each sampled maximum
# refined by golden section to 1e-13 in w), one run per xi.
XIS=(0.01 0.05 0.1 0.2)
WBS=0.1,0.15,0.2,0.3,0.4,0.6,0.8,1,1.5,2,3,4,6,8,10,15,20,30,50,70,100
for xi in "${XIS[@]}"; do
  hbf analytic --law lugre --fe 1 --xi "$xi" --sweep wb --values "$WBS" --out "$OUT/fig11_max_xi$xi.csv"
  if awk -F, 'NR > 1 && $3 == "" { bad = 1 } END { exit !bad }' "$OUT/fig11_max_xi$xi.csv"; then
    die "hbf analytic: no finite maximum of mu_limit for xi = $xi"
  fi
done
for wb in 0.4 1 4 16; do
  hbf analytic --law lugre --fe 1 --wb "$wb" --xi 0.1 --points 4401 --out "$OUT/fig11_lugre_xi0.1_wb$wb.csv"
done
hbf analytic --law coulomb --fe 1 --points 4401 --out "$OUT/fig11_coulomb.csv"

plot <<GP
set output '$OUT/fig10_limit_friction.png'
set multiplot layout 2,1 title "Fig. 10: limit friction coefficient (full stick iff {/Symbol m} >= {/Symbol m}_{limit}); r = 0.1, w_a = 1, w_b = 0.4, {/Symbol x} = 0.01, f_e = 1"
set size 1,0.62
set origin 0,0.33
set lmargin 12
set xrange [0.5:1.6]
set logscale y
set yrange [0.001:100]
set format y '10^{%T}'
set ylabel '{/Symbol m}_{limit}'
set format x ''
set key top left
plot '$OUT/fig10_coulomb.csv' using 'w':'mu_limit' with lines lc rgb '#888888' dt 2 title 'Coulomb (eq. 15, fe outside the root)', \
     '$OUT/fig10_dahl.csv' using 'w':'mu_limit' with lines lc rgb '#1f77b4' title 'Dahl (eq. 25 times f_e)', \
     '$OUT/fig10_lugre.csv' using 'w':'mu_limit' with lines lc rgb '#d62728' title 'LuGre (eq. 27 times f_e)'
set size 1,0.3
set origin 0,0.03
unset logscale y
set format y '%g'
set format x '%g'
set yrange [-0.6:0.4]
set ytics 0.2
set ylabel 'LuGre/Dahl - 1 (%)'
set xlabel 'w = {/Symbol W}/{/Symbol w}_1'
set key bottom left
plot '$OUT/fig10_ratio.csv' using 'w':(100 * (column('ratio') - 1)) with lines lc rgb '#000000' title '100 ({/Symbol m}_{limit}(LuGre) / {/Symbol m}_{limit}(Dahl) - 1): above 0 away from the resonances', \
     0 with lines lc rgb '#888888' dt 2 notitle
unset multiplot
GP

plot <<GP
set output '$OUT/fig11_max_limit_friction.png'
set multiplot layout 1,2 title "Fig. 11: limit friction coefficient of LuGre as the contact stiffness ratio w_b grows (r = 0.1, w_a = 1, f_e = 1)"
set logscale xy
set format y '10^{%T}'
set xlabel 'w_b'
set ylabel 'max_{0.5 <= w <= 1.6} {/Symbol m}_{limit}'
set title 'maximum over w (Dahl, Coulomb: infinite)'
set key top left
xis = "${XIS[*]}"
plot for [xi in xis] sprintf('$OUT/fig11_max_xi%s.csv', xi) using 'wb':'mu_limit_max' with linespoints pt 7 ps 0.5 title sprintf('{/Symbol x} = %s', xi)
unset logscale x
set format x '%g'
set xrange [0.5:1.6]
set yrange [0.001:1000]
set xlabel 'w'
set ylabel '{/Symbol m}_{limit}'
set title 'pointwise: {/Symbol x} = 0.1, w_b -> Coulomb'
plot for [wb in "0.4 1 4 16"] sprintf('$OUT/fig11_lugre_xi0.1_wb%s.csv', wb) using 'w':'mu_limit' with lines title sprintf('w_b = %s', wb), \
     '$OUT/fig11_coulomb.csv' using 'w':'mu_limit' with lines lc rgb '#000000' dt 2 title 'Coulomb'
unset multiplot
GP
wrote "$OUT/fig10_limit_friction.png" "$OUT/fig11_max_limit_friction.png"
