# The SCOTCH ordering strategies of this record, sourced by study.sh and parts.sh: `strat[NAME]` is a strategy
# string in SCOTCH's grammar (its manual, section "Ordering strategy strings"), "" for SCOTCH's default and
# flag:N for SCOTCH_stratGraphOrderBuild's flag N (1: SCOTCH_STRATQUALITY).
# Nested dissection down to 120 vertices; the leaves by halo approximate minimum fill (f), separators by
# Gibbs-Poole-Stockmeyer (g); each separator multilevel (m: coarsened to 100 vertices, greedy graph growing, then
# refined on the way up by the method given).
nd() { echo "n{sep=/(vert>120)?$1;,ole=f{cmin=0,cmax=100000,frat=0.0},ose=g}"; }
ml() { echo "m{rat=0.8,vert=100,low=h{pass=10},asc=$1}"; }
declare -A strat=(
  [default]=""
  [quality]="flag:1"
  [nd-fm0.2]="$(nd "$(ml 'f{bal=0.2}')")"                        # FM refinement, imbalance up to 20%
  [nd-fm0.5]="$(nd "$(ml 'f{bal=0.5}')")"                        # looser: up to 50%
  [nd-band0.5]="$(nd "$(ml 'b{width=3,bnd=f{bal=0.5},org=(|h{pass=10})f{bal=0.5}}')")"  # FM on a band graph
  [nd-best2-fm0.5]="$(nd "($(ml 'f{bal=0.5}')|$(ml 'f{bal=0.5}'))")"  # the better of two separators
)
