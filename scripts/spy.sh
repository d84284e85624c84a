#!/usr/bin/env bash
# Starts lcm-spy with the socc message types, so it decodes socc traffic (see docs/lcm.md).
#   scripts/spy.sh [-b BUILD_DIR] [LCM_URL]
# BUILD_DIR (default: build, or $SOCC_BUILD_DIR) must hold lcmtypes/socc_lcmtypes.jar, which
# every socc build makes. LCM_URL defaults to the socc default and must stay on this machine
# (udpm://239.x.y.z:PORT?ttl=0).
# Debian's /usr/bin/lcm-spy passes -Xincgc, which Java 17 rejects, so java is run directly.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SOCC_BUILD_DIR:-$root/build}"
url="udpm://239.255.76.67:7667?ttl=0"

usage() { sed -n '2,7p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    -b | --build) build="$(realpath -m "$2")"; shift 2 ;;
    -*) echo "spy.sh: unknown option $1" >&2; usage >&2; exit 2 ;;
    *) url="$1"; shift ;;
  esac
done

if ! [[ "$url" =~ ^udpm://239\.[0-9]{1,3}\.[0-9]{1,3}\.[0-9]{1,3}:[0-9]{1,5}\?ttl=0$ ]]; then
  echo "spy.sh: refusing LCM URL '$url': only udpm://239.x.y.z:PORT?ttl=0 stays on this machine" >&2
  exit 2
fi
jar="$build/lcmtypes/socc_lcmtypes.jar"
# Installed as <prefix>/bin/socc-spy, the jar is in <prefix>/share/socc/java.
installed_jar="$root/share/socc/java/socc_lcmtypes.jar"
[ ! -f "$jar" ] && [ -f "$installed_jar" ] && jar="$installed_jar"
[ -f "$jar" ] || { echo "spy.sh: $jar not found: build socc first (or pass -b BUILD_DIR)" >&2; exit 1; }
lcm_jar=/usr/share/java/lcm.jar
[ -f "$lcm_jar" ] || { echo "spy.sh: $lcm_jar not found: apt-get install liblcm-java" >&2; exit 1; }
command -v java >/dev/null || { echo "spy.sh: java not found: apt-get install default-jre" >&2; exit 1; }

# lcm-spy finds message types by scanning the jars on CLASSPATH; jchart2d draws its plots.
classpath="$lcm_jar:$jar"
[ -f /usr/share/java/jchart2d.jar ] && classpath="$classpath:/usr/share/java/jchart2d.jar"
export CLASSPATH="$classpath"
exec java -Djava.net.preferIPv4Stack=true -Xmx256m -cp "$classpath" lcm.spy.Spy --lcm-url="$url"
