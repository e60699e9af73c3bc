#!/bin/sh
# expect_refusal.sh PATTERN COMMAND...: runs COMMAND with at most 1 GiB of address space and 60 s;
# passes when it exits with status 1 (hdm's error exit, not a signal, a timeout or an
# out-of-memory) and its standard error contains PATTERN (a fixed string: the clear message).
# Under AddressSanitizer (scripts/test_asan.sh sets HDM_SANITIZED=1) the address-space limit cannot
# apply (ASan reserves terabytes of shadow memory); its hard_rss_limit_mb=1024 kills instead.
pattern=$1
shift
if [ "${HDM_SANITIZED:-0}" = 1 ]; then
  err=$(timeout 60 "$@" 2>&1 >/dev/null)
else
  err=$( (ulimit -v 1048576; timeout 60 "$@") 2>&1 >/dev/null)
fi
rc=$?
printf '%s\n' "$err"
if [ "$rc" -ne 1 ]; then
  echo "expect_refusal: exit status $rc, expected 1 (124: timeout, >128: signal)" >&2
  exit 1
fi
case "$err" in
  *"$pattern"*) exit 0 ;;
esac
echo "expect_refusal: the message lacks: $pattern" >&2
exit 1
