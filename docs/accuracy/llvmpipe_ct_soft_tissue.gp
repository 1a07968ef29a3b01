# Written by `penumbra bench accuracy`; `gnuplot llvmpipe_ct_soft_tissue.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe_ct_soft_tissue.png"
svg = "llvmpipe_ct_soft_tissue.svg"
width = 960
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n128x128, lights (az,el) 10,45, sample distance 1/512, 1/256, tf ct_soft_tissue, Blinn-Phong on"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
panels = 1
modes = "phong half_angle sbrc sbrc_cone"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 4
variant_kinds = "1 2 3"
array panel_title[1] = ["cranium_ct"]
array y_range[1] = ["[19.0:51.0]"]
array ref_panel[4] = [1, 1, 1, 1]
array ref_ms[4] = [1937.56, 1229.03, 636.76, 312.821]
array ref_text[4] = ["reference 1/512 no skipping (PSNR inf)", "reference 1/512 (PSNR inf)", "reference 1/256 no skipping (PSNR inf)", "reference 1/256 (PSNR inf)"]
array ref_row[4] = [0, 1, 2, 3]
$front << EOD
1 26.2653 20.0584 "32/128"
1 88.7779 26.8811 "128/128"
1 116.874 39.1444 "64/128"
1 124.745 39.2208 "256/128"
1 144.141 47.0451 "64/128"
1 246.656 48.1895 "32/128"
EOD
$all << EOD
1 1 116.792 22.3533
1 1 89.8584 22.1921
1 2 26.4666 20.0584
1 2 26.2653 20.0584
1 2 113.629 22.1005
1 2 115.97 22.1005
1 2 91.0377 26.8811
1 2 88.7779 26.8811
1 2 340.835 32.4847
1 2 477.641 32.4847
1 3 246.656 48.1895
1 3 136.501 39.2174
1 3 144.141 47.0451
1 3 116.874 39.1444
1 3 197.39 46.2851
1 3 129.135 39.1327
1 3 257.949 46.4526
1 3 124.745 39.2208
1 4 427.094 46.4547
1 4 289.208 38.9051
1 4 463.751 47.6692
1 4 272.307 39.1960
1 4 267.385 45.0868
1 4 133.645 38.8684
1 4 251.944 44.9630
1 4 190.264 38.8982
EOD
$own << EOD
1 1 89.8584 22.1921
1 1 116.792 22.3533
1 2 26.2653 20.0584
1 2 88.7779 26.8811
1 2 340.835 32.4847
1 3 116.874 39.1444
1 3 124.745 39.2208
1 3 144.141 47.0451
1 3 246.656 48.1895
1 4 133.645 38.8684
1 4 190.264 38.8982
1 4 251.944 44.9630
1 4 267.385 45.0868
1 4 427.094 46.4547
1 4 463.751 47.6692
EOD
$variants << EOD
1 1 329.91 22.3533 1
1 1 353.885 22.3428 2
1 1 1710.43 22.3653 3
1 1 3023.1 22.3657 3
1 1 125.976 22.3428 2
1 1 942.722 22.3653 3
1 1 1307.25 22.3657 3
1 1 189.987 22.1921 1
1 1 225.598 22.2220 2
1 1 792.281 22.3269 3
1 1 1499 22.3294 3
1 1 79.0627 22.2220 2
1 1 419.793 22.3269 3
1 1 649.772 22.3294 3
1 2 31.9923 20.0584 1
1 2 32.6498 20.0584 1
1 2 112.176 22.1005 1
1 2 76.744 22.1005 1
1 2 86.3875 26.8811 1
1 2 99.0213 26.8811 1
1 2 409.243 32.4847 1
1 2 321.898 32.4847 1
1 3 660.381 48.1895 1
1 3 763.973 44.0040 2
1 3 4793.76 45.7229 3
1 3 8628.76 45.7420 3
1 3 229.959 44.0040 2
1 3 1029.53 45.7229 3
1 3 1761.73 45.7420 3
1 3 407.354 39.2174 1
1 3 335.054 39.9125 2
1 3 1977.28 45.4624 3
1 3 3444.58 45.5626 3
1 3 145.379 39.9125 2
1 3 633.25 45.4624 3
1 3 1070.84 45.5626 3
1 3 391.25 47.0451 1
1 3 549.809 43.4160 2
1 3 3058.47 44.9170 3
1 3 5304.95 44.9469 3
1 3 173.151 43.4160 2
1 3 948.556 44.9170 3
1 3 1632.86 44.9469 3
1 3 257.523 39.1444 1
1 3 345.612 39.8662 2
1 3 1620.01 44.6795 3
1 3 3358.64 44.7691 3
1 3 90.0103 39.8662 2
1 3 513.637 44.6795 3
1 3 914.826 44.7691 3
1 3 413.829 46.2851 1
1 3 379.235 43.0656 2
1 3 1911.2 44.3643 3
1 3 3463.34 44.3803 3
1 3 245.998 43.0656 2
1 3 1071.36 44.3643 3
1 3 1915.63 44.3803 3
1 3 203.93 39.1327 1
1 3 235.931 39.8544 2
1 3 1195.65 44.1683 3
1 3 2168.14 44.2255 3
1 3 123.714 39.8544 2
1 3 622.823 44.1683 3
1 3 1155.6 44.2255 3
1 3 547.934 46.4526 1
1 3 595.976 43.1551 2
1 3 3176.26 44.3779 3
1 3 5670.49 44.3993 3
1 3 191.304 43.1551 2
1 3 1133.36 44.3779 3
1 3 2174.67 44.3993 3
1 3 355.128 39.2208 1
1 3 233.987 40.0002 2
1 3 1182.21 44.1975 3
1 3 2414.96 44.2356 3
1 3 169.956 40.0002 2
1 3 729.66 44.1975 3
1 3 1356.38 44.2356 3
1 4 1089.85 46.4547 1
1 4 1259.93 43.4060 2
1 4 4588.67 44.8123 3
1 4 8259.6 44.8216 3
1 4 517.905 43.4060 2
1 4 2684.84 44.8123 3
1 4 4607.95 44.8216 3
1 4 601.735 38.9051 1
1 4 382.477 39.6388 2
1 4 1959.48 44.6168 3
1 4 3497.91 44.6844 3
1 4 258.686 39.6388 2
1 4 1481.55 44.6168 3
1 4 2699.07 44.6844 3
1 4 738.446 47.6692 1
1 4 811.319 43.8258 2
1 4 4940.28 45.3928 3
1 4 7985.24 45.4328 3
1 4 505.944 43.8258 2
1 4 2344.11 45.3928 3
1 4 4047.95 45.4328 3
1 4 422.352 39.1960 1
1 4 362.839 39.8251 2
1 4 2029.85 45.2010 3
1 4 3545.12 45.2789 3
1 4 191.27 39.8251 2
1 4 998.406 45.2010 3
1 4 1784.25 45.2789 3
1 4 732.199 45.0868 1
1 4 725.902 42.5549 2
1 4 4095.1 43.6845 3
1 4 6932.68 43.7108 3
1 4 220.589 42.5549 2
1 4 1600.22 43.6845 3
1 4 2724.04 43.7108 3
1 4 385.925 38.8684 1
1 4 422.506 39.3874 2
1 4 2140.5 43.8211 3
1 4 3838.06 43.8769 3
1 4 174.836 39.3874 2
1 4 1007.44 43.8211 3
1 4 1711.5 43.8769 3
1 4 901.672 44.9630 1
1 4 828.114 42.3413 2
1 4 4356.27 43.5264 3
1 4 8215.49 43.5314 3
1 4 282.645 42.3413 2
1 4 1420.83 43.5264 3
1 4 2695.87 43.5314 3
1 4 635.677 38.8982 1
1 4 471.938 39.5436 2
1 4 2379.51 43.5990 3
1 4 4283.12 43.6381 3
1 4 226.226 39.5436 2
1 4 1208.69 43.5990 3
1 4 2175.65 43.6381 3
EOD

# The accuracy plot of `penumbra bench accuracy` (installed as share/penumbra/plots/accuracy.gp).
# The benchmark writes its data and these variables above this text, into one script:
#   png, svg            the images to write (no folder: run in their folder)
#   width               pixels; 620 per panel, at least 960
#   title_text          the figure's title; x_label the x axis's
#   panels              one per volume; panel_title[v], y_range[v] ("[low:high]" or "[*:*]")
#   modes               the measured modes, reference aside, as words; a mode's index is its word
#   style_modes, style_colours, style_points   every mode's plot colour and point type (the
#                       mode table's), as words in the same order
#   ref_count           references; ref_panel[r], ref_ms[r], ref_text[r], ref_row[r]
#   $front              panel, frame ms, PSNR, label: the Pareto front over all modes
#   $all                panel, mode, frame ms, PSNR: every setting (means over the lights)
#   $own                panel, mode, frame ms, PSNR: each mode's own Pareto front
#   $variants           panel, mode, ms, PSNR, kind: the settings that differ from the request's
#                       defaults, by kind: 1 without empty-space skipping, 2 jittered, 3 refined
#                       (ms: the still and its steps in all)
#   variant_kinds       the kinds $variants holds, as words
# One panel per volume: every setting of a mode as a small mark, the mode's own front as its
# curve, the front over all modes as a wide grey band, the reference's time as a vertical line
# (its PSNR is infinite), and the variants as open marks in their mode's colour.

style_index(name) = sum [i=1:words(style_modes)] (word(style_modes, i) eq name ? i : 0)
colour(name) = style_index(name) > 0 ? word(style_colours, style_index(name)) : "#404040"
point(name) = style_index(name) > 0 ? int(word(style_points, style_index(name))) : 3
kind(k) = int(word(variant_kinds, k))
variant_point(kind) = kind == 1 ? 8 : (kind == 2 ? 10 : 12)
variant_title(kind) = kind == 1 ? "no empty-space skipping" : (kind == 2 ? "jittered" : "jittered and refined (time of all steps)")

# The plot's clauses, as macros: a plot with no variants leaves theirs out (gnuplot evaluates an
# iteration's clause once even when the iteration is empty).
common_plot = '$front using ($1 == v ? $2 : NaN):3 with linespoints lw 9 lc rgb "#d0d0d0" pt 6 ps 2.2 title "Pareto front (all methods)", '. \
    '$front using ($1 == v ? $2 : NaN):3:4 with labels right offset -1.2,0 font ",8" tc rgb "#505050" notitle, '. \
    'for [m=1:words(modes)] $all using ($1 == v && $2 == m ? $3 : NaN):4 with points pt (point(word(modes, m)) - 1) ps 0.6 lc rgb colour(word(modes, m)) notitle, '. \
    'for [m=1:words(modes)] $own using ($1 == v && $2 == m ? $3 : NaN):4 with linespoints lw 2 pt point(word(modes, m)) ps 1.1 lc rgb colour(word(modes, m)) title word(modes, m)'
variant_plot = 'for [m=1:words(modes)] for [k=1:words(variant_kinds)] $variants using ($1 == v && $2 == m && $5 == kind(k) ? $3 : NaN):4 with points pt variant_point(kind(k)) ps 1.3 lw 1.5 lc rgb colour(word(modes, m)) notitle, '. \
    'for [k=1:words(variant_kinds)] NaN with points pt variant_point(kind(k)) ps 1.3 lw 1.5 lc rgb "#404040" title variant_title(kind(k))'

set logscale x
set grid xtics ytics mxtics lc rgb "#e8e8e8"
set xlabel x_label
set ylabel "PSNR vs reference, dB (higher is better); grey labels: slices n / light-buffer R"
set key bottom right box opaque font ",9" spacing 1.1
set mxtics 10

do for [pass=1:2] {
    if (pass == 1) {
        set terminal pngcairo size width,600 noenhanced font "DejaVu Sans,10"
        set output png
    } else {
        set terminal svg size width,600 dynamic noenhanced font "DejaVu Sans,10" background "#ffffff"
        set output svg
    }
    set multiplot layout 1,panels title title_text font ",12"
    do for [v=1:panels] {
        set title panel_title[v]
        unset arrow
        unset label
        eval "set yrange " . y_range[v]
        do for [r=1:ref_count] {
            if (ref_panel[r] == v) {
                set arrow from ref_ms[r], graph 0 to ref_ms[r], graph 1 nohead dt 2 lw 1.5 lc rgb "#c00000"
                set label ref_text[r] at ref_ms[r], graph (0.97 - 0.05 * ref_row[r]) right offset -0.5,0 tc rgb "#c00000" font ",9"
            }
        }
        if (words(variant_kinds) > 0) {
            plot @common_plot, @variant_plot
        } else {
            plot @common_plot
        }
    }
    unset multiplot
}
set output
