# nftables rules of scripts/two-hosts (docs/MULTI_HOST.md, "Threat model"), sourced by it:
#   firewall_up ADDR PEER PORT   this host's ROS ports reachable from PEER on ADDR's interface
#                                and from loopback only; exits 1 naming what failed
#   firewall_down                removes the table (nothing if it is not there)
# ROS 1 servers listen on every interface whatever ROS_IP says: the master on its port, each
# node's XML-RPC and TCPROS servers on a port the kernel picks from its ephemeral range. The
# rules cover those ports (TCP and UDP, IPv4 and IPv6) on every interface; other ports (ssh) and
# replies to this host's own connections (conntrack: established) are left alone. New
# connections from anyone else are dropped (the sender sees a timeout, not a refusal), counted.
# The rules live in a table of their own, replaced as a whole if a killed run left it.
# shellcheck shell=bash
fw_table="aar_two_hosts"

# The interface that holds ADDR.
link_device() {
  ip -o -4 addr show | awk -v a="$1" '{split($4, p, "/"); if (p[1] == a) {print $2; exit}}'
}

# The ROS ports as an nft set's elements: the master's PORT and the ephemeral range.
ros_ports() {
  local lo hi
  read -r lo hi </proc/sys/net/ipv4/ip_local_port_range
  if [ "$1" -ge "$lo" ] && [ "$1" -le "$hi" ]; then echo "$lo-$hi"; else echo "$1, $lo-$hi"; fi
}

firewall_rules() {  # ADDR PEER PORT: the table, as nft -f reads it
  local dev ports
  dev="$(link_device "$1")" ports="$(ros_ports "$3")"
  cat <<EOF
table inet $fw_table
delete table inet $fw_table
table inet $fw_table {
  chain input {
    type filter hook input priority filter - 10; policy accept;
    iif "lo" accept
    ct state established,related accept
    iifname "$dev" ip saddr $2 meta l4proto { tcp, udp } th dport { $ports } accept
    meta l4proto { tcp, udp } th dport { $ports } counter drop comment "ROS ports: $2 on $dev only"
  }
}
EOF
}

firewall_up() {  # ADDR PEER PORT
  local why
  command -v nft >/dev/null ||
    { echo "two-hosts: 'nft' (nftables) is not installed: scripts/setup installs it" \
      "(or --no-firewall, unprotected)" >&2; exit 1; }
  nft list table inet "$fw_table" >/dev/null 2>&1 &&
    echo "two-hosts: replacing the nftables table inet $fw_table a previous run left"
  why="$(firewall_rules "$@" | nft -f - 2>&1)" ||
    { echo "two-hosts: cannot install the nftables table inet $fw_table: nft says: $why" \
      "(it needs root, CAP_NET_ADMIN)" >&2; exit 1; }
  echo "two-hosts: firewall (nftables table inet $fw_table): this host's ROS ports" \
    "($(ros_ports "$3")) reachable only from $2 on $(link_device "$1") and from loopback;" \
    "removed when this script ends"
}

firewall_down() { nft delete table inet "$fw_table" 2>/dev/null || true; }
