# Written by `penumbra bench accuracy`; `gnuplot llvmpipe_mri_brain.gp` in this folder redraws the PNG and SVG.
# x: median frame time with the light buffer cached, y: PSNR vs the reference; marks: every setting; curves: each method's Pareto front; open marks: no skipping, jittered, refined (at the time its steps take in all).
png = "llvmpipe_mri_brain.png"
svg = "llvmpipe_mri_brain.svg"
width = 960
title_text = "Penumbra: accuracy vs frame time on llvmpipe (LLVM 15.0.6, 256 bits)\n128x128, lights (az,el) 10,45, sample distance 1/512, 1/256, tf mri_brain, Blinn-Phong on"
x_label = "frame time, ms (wall clock, median; no GPU timer queries on this device; log scale)"
panels = 1
modes = "phong half_angle sbrc sbrc_cone"
style_modes = "dvr phong half_angle sbrc sbrc_shell sbrc_cone reference"
style_colours = "#7f7f7f #000000 #e07b00 #1f5fbf #2a9d3a #9b30c0 #d62728"
style_points = "5 7 9 11 13 15 17"
ref_count = 4
variant_kinds = "1 2 3"
array panel_title[1] = ["ch2bet"]
array y_range[1] = ["[20.0:53.0]"]
array ref_panel[4] = [1, 1, 1, 1]
array ref_ms[4] = [1736.45, 924.056, 569.974, 338.869]
array ref_text[4] = ["reference 1/512 no skipping (PSNR inf)", "reference 1/512 (PSNR inf)", "reference 1/256 no skipping (PSNR inf)", "reference 1/256 (PSNR inf)"]
array ref_row[4] = [0, 1, 2, 3]
$front << EOD
1 39.6596 22.6466 "32/128"
1 63.1717 24.6795 "64/128"
1 85.5805 44.4383 "64/128"
1 107.717 44.8825 "32/128"
1 134.235 48.8719 "64/128"
1 187.49 50.3577 "32/128"
EOD
$all << EOD
1 1 93.9387 21.6367
1 1 63.9316 21.5779
1 2 39.6596 22.6466
1 2 46.6083 22.6466
1 2 92.245 24.6795
1 2 63.1717 24.6795
1 2 115.539 29.3424
1 2 95.6911 29.3424
1 2 252.184 34.9141
1 2 289.401 34.9141
1 3 187.49 50.3577
1 3 107.717 44.8825
1 3 134.235 48.8719
1 3 85.5805 44.4383
1 3 219.789 47.9537
1 3 135.941 44.2752
1 3 202.316 47.0861
1 3 131.904 43.9441
1 4 297.926 47.7559
1 4 174.895 43.7629
1 4 328.318 44.7782
1 4 185.579 42.4013
1 4 320.792 47.1023
1 4 230.483 43.7873
1 4 275.908 45.2432
1 4 141.338 42.7699
EOD
$own << EOD
1 1 63.9316 21.5779
1 1 93.9387 21.6367
1 2 39.6596 22.6466
1 2 63.1717 24.6795
1 2 95.6911 29.3424
1 2 252.184 34.9141
1 3 85.5805 44.4383
1 3 107.717 44.8825
1 3 134.235 48.8719
1 3 187.49 50.3577
1 4 141.338 42.7699
1 4 174.895 43.7629
1 4 230.483 43.7873
1 4 275.908 45.2432
1 4 297.926 47.7559
EOD
$variants << EOD
1 1 300.226 21.6367 1
1 1 294.671 21.6292 2
1 1 1634.7 21.6407 3
1 1 3201.95 21.6404 3
1 1 81.9235 21.6292 2
1 1 359.032 21.6407 3
1 1 672.34 21.6404 3
1 1 150.314 21.5779 1
1 1 168.507 21.6049 2
1 1 1179.79 21.6265 3
1 1 2093.03 21.6276 3
1 1 49.3061 21.6049 2
1 1 213.319 21.6265 3
1 1 395.296 21.6276 3
1 2 26.4893 22.6466 1
1 2 31.4151 22.6466 1
1 2 52.4518 24.6795 1
1 2 45.0595 24.6795 1
1 2 92.505 29.3424 1
1 2 110.22 29.3424 1
1 2 167.996 34.9141 1
1 2 195.875 34.9141 1
1 3 685.882 50.3577 1
1 3 754.529 48.2009 2
1 3 4026.33 49.1806 3
1 3 7901.91 49.1653 3
1 3 206.685 48.2009 2
1 3 1296.21 49.1806 3
1 3 1870.73 49.1653 3
1 3 437.373 44.8825 1
1 3 355.942 45.0148 2
1 3 1972.91 49.0035 3
1 3 3476.73 49.0643 3
1 3 143.149 45.0148 2
1 3 629.412 49.0035 3
1 3 1202.74 49.0643 3
1 3 989.942 48.8719 1
1 3 899.899 47.2126 2
1 3 4148.12 47.9766 3
1 3 6446.5 47.9626 3
1 3 148.458 47.2126 2
1 3 1327.73 47.9766 3
1 3 1709.04 47.9626 3
1 3 435.216 44.4383 1
1 3 310.201 44.5434 2
1 3 2239.44 47.7936 3
1 3 3624.45 47.8442 3
1 3 121.616 44.5434 2
1 3 1234.59 47.7936 3
1 3 2035.89 47.8442 3
1 3 687.933 47.9537 1
1 3 812.153 46.6477 2
1 3 3379.62 47.2892 3
1 3 6519.81 47.3139 3
1 3 201.643 46.6477 2
1 3 1057.87 47.2892 3
1 3 2007.6 47.3139 3
1 3 479.525 44.2752 1
1 3 433.954 44.3267 2
1 3 2011.41 47.1321 3
1 3 3489.36 47.1921 3
1 3 123.806 44.3267 2
1 3 782.533 47.1321 3
1 3 1405.74 47.1921 3
1 3 725.875 47.0861 1
1 3 575.62 45.9572 2
1 3 2416.98 46.5285 3
1 3 4518.37 46.5311 3
1 3 205.499 45.9572 2
1 3 1043.19 46.5285 3
1 3 1961.63 46.5311 3
1 3 288.889 43.9441 1
1 3 229.894 43.9606 2
1 3 1070.72 46.3702 3
1 3 1962.86 46.4286 3
1 3 128.323 43.9606 2
1 3 591.45 46.3702 3
1 3 1260.08 46.4286 3
1 4 829.482 47.7559 1
1 4 763.944 46.4568 2
1 4 3889.44 46.9950 3
1 4 6926.81 46.9986 3
1 4 296.842 46.4568 2
1 4 1107.89 46.9950 3
1 4 1997.46 46.9986 3
1 4 450.826 43.7629 1
1 4 400.255 43.8220 2
1 4 1511.85 46.8809 3
1 4 2787.69 46.9131 3
1 4 134.27 43.8220 2
1 4 663.313 46.8809 3
1 4 1193.96 46.9131 3
1 4 943.949 44.7782 1
1 4 940.527 44.0616 2
1 4 5012.16 44.3567 3
1 4 8846.48 44.3741 3
1 4 299.936 44.0616 2
1 4 1849.46 44.3567 3
1 4 3063.75 44.3741 3
1 4 535.948 42.4013 1
1 4 564.213 42.3529 2
1 4 2541.59 44.2977 3
1 4 4785.78 44.3201 3
1 4 209.381 42.3529 2
1 4 929.857 44.2977 3
1 4 1779.76 44.3201 3
1 4 825.106 47.1023 1
1 4 961.957 45.9278 2
1 4 4854.29 46.4335 3
1 4 8090.8 46.4743 3
1 4 269.635 45.9278 2
1 4 1213.57 46.4335 3
1 4 2121.71 46.4743 3
1 4 427.706 43.7873 1
1 4 587.927 43.7874 2
1 4 2428.95 46.3497 3
1 4 4356.58 46.3846 3
1 4 186.04 43.7874 2
1 4 855.2 46.3497 3
1 4 1367.77 46.3846 3
1 4 703.548 45.2432 1
1 4 797.652 44.3846 2
1 4 4191.61 44.8243 3
1 4 7090.77 44.8342 3
1 4 186.881 44.3846 2
1 4 1223.09 44.8243 3
1 4 2319.89 44.8342 3
1 4 313.949 42.7699 1
1 4 455.555 42.8899 2
1 4 2094.07 44.8180 3
1 4 4343.06 44.8603 3
1 4 155.977 42.8899 2
1 4 503.954 44.8180 3
1 4 1072.25 44.8603 3
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
